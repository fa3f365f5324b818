// solve/times_many.hpp -- y = B x for k vectors at once, for the plugin solve/cholmod_columns.cpp (included inside its
// namespace, after cholmod_arrays.hpp): FreeFEM's own product (HashMatrix::addMatMul), its entries in the same order
// and each vector's sums in that order, so each block has the bits of B * x; B's entries are read once for the k
// (-np N: the k GMRES of S's columns in step, solve/ffddm_solve.idp). x, y: the k blocks one after the other.
long timesMany(Matrice_Creuse< double > *const &pB, KN< double > *const &y, KN< double > *const &x, const long &k) {
  HashMatrix< int, double > *H = pB->pHM( );
  if (!H || H->fortran) ExecError("matrixTimesMany: B must be a sparse matrix of FreeFEM's");
  const long n = H->n, m = H->m;
  const double *X = contiguous(x, m * k, "x");
  double *Y = output(y, n * k, "y");
  std::fill(Y, Y + n * k, 0.);
  const int *ii = H->i, *jj = H->j;
  const double *aa = H->aij;
  for (size_t e = 0; e < H->nnz; ++e) {
    const double a = aa[e];
    const int r = ii[e], c = jj[e];
    for (long s = 0; s < k; ++s) Y[s * n + r] += a * X[s * m + c];
    if (H->half && r != c)
      for (long s = 0; s < k; ++s) Y[s * n + c] += a * X[s * m + r];
  }
  return 0;
}
