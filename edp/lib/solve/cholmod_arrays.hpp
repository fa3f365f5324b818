// solve/cholmod_arrays.hpp -- FreeFEM arrays as CHOLMOD sees them, for the plugin solve/cholmod_columns.cpp (included
// inside its namespace, after ff++.hpp and cholmod.h): a dense view without a copy, and the checks of an input or output.
// a dense view of a contiguous FreeFEM array (no copy)
cholmod_dense view(double *p, long n, long ncol = 1) {
  cholmod_dense d;
  d.nrow = n;  d.ncol = ncol;  d.nzmax = n * ncol;  d.d = n;  d.x = p;  d.z = nullptr;
  d.xtype = CHOLMOD_REAL;  d.dtype = CHOLMOD_DOUBLE;
  return d;
}

KN< double > &contiguous(KN< double > *a, long n, const char *what) {
  if (a->N( ) != n) ExecError(std::string("cholmod_columns: ") + what + " has the wrong size");
  if (a->step != 1) ExecError(std::string("cholmod_columns: ") + what + " is not contiguous");
  return *a;
}

// an output array: sized n if it is not
KN< double > &output(KN< double > *a, long n, const char *what) {
  if (a->N( ) != n) a->resize(n);
  return contiguous(a, n, what);
}
