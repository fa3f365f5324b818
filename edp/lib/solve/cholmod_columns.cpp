// solve/cholmod_columns.cpp -- a FreeFEM plugin (built by `make plugins` with ff-c++ into build/plugins/): the
// Cholesky factor P A P' = L L' of the step's matrix A (CHOLMOD, as FreeFEM's own sparsesolverSym builds it), with
// its two triangular halves apart (P A P' = L D L' when CHOLMOD keeps a simplicial factor: D = I for L L'), and
// columns W_k = L^-1 P e_d kept sparse. With W = L^-1 P C' the Schur complement of the contact rows is
// S = C A^-1 C' = W' D^-1 W, C A^-1 b = W' D^-1 (L^-1 P b) and A^-1 (b - C' lm) = P' L^-T D^-1 (L^-1 P b - W lm):
// a step with contact costs one forward and one backward solve, the cost of one solve (contact/active_set_factor.idp).
//
//   int h = cholmodFactor(A, ordering, kind)  ordering: default (CHOLMOD's own choice, FreeFEM's), amd, metis,
//                                             nesdis; kind: auto, supernodal, simplicial. -1: A not positive definite;
//                                             -2: L does not fit in what this process's memory limit leaves
//   real m = cholmodRefusedMiB(0)             then: the MiB L needs (0), the MiB the limit left (1)
//   cholmodSolve(h, x, b)                     x = A^-1 b
//   cholmodForward(h, y, b)                   y = L^-1 P b
//   cholmodBackward(h, x, y)                  x = P' L^-T D^-1 y
//   int k0 = cholmodAddColumns(h, dofs)       W_{k0 + i} = L^-1 P e_{dofs[i]}, in blocks of right-hand sides
//   cholmodColumnDots(h, cols, y, out)        out[i] = W_{cols[i]}' D^-1 y
//   cholmodColumnAxpy(h, cols, coef, y)       y += sum_i coef[i] W_{cols[i]}
//   cholmodColumnGram(h, rows, col, out)      out[i] = W_{rows[i]}' D^-1 W_col
//   real e = cholmodColumnEntries(h)          the entries kept for the columns
//   real s = cholmodFactorEntries(h)          the entries of L
//   real t = wallSeconds()                    a steady wall clock, in seconds (FreeFEM's time() counts whole seconds)
#include "ff++.hpp"
#include "AFunction_ext.hpp"
#include <cholmod.h>
#include <vector>
#include <chrono>
#include "memory_left.hpp"

namespace {
struct ColumnFactor {
  cholmod_common c;
  cholmod_factor *L = nullptr;  long n = 0;
  std::vector< std::vector< int > > index;    // the nonzero rows of each column W_k
  std::vector< std::vector< double > > value;
  std::vector< double > scatter, dinv;        // D^-1 W_col scattered (the Gram products); D^-1 (1 for L L')
  double entries = 0;
};
std::vector< ColumnFactor * > factors;

ColumnFactor *factorOf(long h) {
  if (h < 0 || h >= (long)factors.size( ) || !factors[h]) ExecError("cholmod_columns: no such factor");
  return factors[h];
}

#include "cholmod_arrays.hpp"    // view, contiguous, output
double refusedMiB[2] = {0, 0};      // the last refusal's: what L needed, what the limit left

// x = op(b) for one CHOLMOD system, into x (b and x may not overlap)
void solveInto(ColumnFactor *f, int sys, double *x, double *b, long ncol = 1) {
  cholmod_dense B = view(b, f->n, ncol);
  cholmod_dense *X = cholmod_solve(sys, f->L, &B, &f->c);
  if (!X) ExecError("cholmod_columns: a solve failed");
  std::copy((double *)X->x, (double *)X->x + f->n * ncol, x);
  cholmod_free_dense(&X, &f->c);
}

long factorise(Matrice_Creuse< double > *const &pA, string *const &ordering, string *const &kind) {
  HashMatrix< int, double > *H = pA->pHM( );
  if (!H || H->n != H->m) ExecError("cholmod_columns: A must be a square sparse matrix");
  ColumnFactor *f = new ColumnFactor;
  cholmod_start(&f->c);
  const string &o = *ordering, &k = *kind;
  if (o != "default") {
    f->c.nmethods = 1;
    if (o == "amd") f->c.method[0].ordering = CHOLMOD_AMD;
    else if (o == "metis") f->c.method[0].ordering = CHOLMOD_METIS;
    else if (o == "nesdis") f->c.method[0].ordering = CHOLMOD_NESDIS;
    else ExecError("cholmod_columns: ordering must be default, amd, metis or nesdis");
  }
  if (k == "supernodal") f->c.supernodal = CHOLMOD_SUPERNODAL;
  else if (k == "simplicial") f->c.supernodal = CHOLMOD_SIMPLICIAL;
  else if (k != "auto") ExecError("cholmod_columns: kind must be auto, supernodal or simplicial");
  // the upper triangle in compressed columns, as FreeFEM's CHOLMOD solver takes it (VirtualSolverSparseSuite.hpp)
  int *Ap = nullptr, *Ai = nullptr;
  double *Ax = nullptr;
  cholmod_sparse A;
  A.nrow = A.ncol = H->n;
  if (H->half) {
    H->CSR(Ap, Ai, Ax);
    A.nzmax = H->nnz;
  } else
    A.nzmax = H->CSC_U(Ap, Ai, Ax);
  A.p = Ap;  A.i = Ai;  A.x = Ax;  A.nz = nullptr;  A.z = nullptr;
  A.stype = 1;  A.itype = CHOLMOD_INT;  A.xtype = CHOLMOD_REAL;  A.dtype = CHOLMOD_DOUBLE;  A.sorted = 1;  A.packed = 1;
  f->n = H->n;
  f->L = cholmod_analyze(&A, &f->c);
  if (!f->L) ExecError("cholmod_columns: the analysis of A failed");
  // refused when L (as the analysis counts it) and OpenBLAS's 128 MiB work buffer do not fit what the memory limit
  // leaves: a process that would fail inside CHOLMOD, or wait for ever in OpenBLAS's allocator, says so instead
  double need = (f->L->is_super ? f->L->xsize * 8. + f->L->ssize * 4. + 134217728. : f->c.lnz * 12.) / 1048576.;
  double left = memoryLeftMiB( );
  bool fits = (left < 0 || need <= left);
  if (fits) cholmod_factorize(&A, f->L, &f->c);
  else refusedMiB[0] = need, refusedMiB[1] = left;
  if (!H->half) { delete[] Ap;  delete[] Ai;  delete[] Ax; }    // (CSC_U made copies)
  if (!fits || f->c.status != CHOLMOD_OK || f->L->minor < (size_t)f->n) {
    cholmod_free_factor(&f->L, &f->c);
    cholmod_finish(&f->c);
    delete f;
    return fits ? -1 : -2;
  }
  // (FreeFEM's own settings otherwise: its solves and these are the same to the last bit)
  f->scatter.assign(f->n, 0.);
  f->dinv.assign(f->n, 1.);
  if (!f->L->is_ll) {    // simplicial L D L': d_k is the first entry of column k
    const int *Lp = (const int *)f->L->p;
    const double *Lx = (const double *)f->L->x;
    for (long k = 0; k < f->n; ++k) f->dinv[k] = 1. / Lx[Lp[k]];
  }
  factors.push_back(f);
  return (long)factors.size( ) - 1;
}

long solveFull(const long &h, KN< double > *const &x, KN< double > *const &b) {
  ColumnFactor *f = factorOf(h);
  solveInto(f, CHOLMOD_A, output(x, f->n, "x"), contiguous(b, f->n, "b"));
  return 0;
}
// k systems at once, b and x their columns one after the other (CHOLMOD reads L once for all k)
long solveMany(const long &h, KN< double > *const &x, KN< double > *const &b, const long &k) {
  ColumnFactor *f = factorOf(h);
  solveInto(f, CHOLMOD_A, output(x, f->n * k, "x"), contiguous(b, f->n * k, "b"), k);
  return 0;
}

// out = second(first(in)): a half of the solve, its permutation on the outer side
long twoSystems(const long &h, KN< double > *out, KN< double > *in, int first, int second, const char *outName,
                const char *inName) {
  ColumnFactor *f = factorOf(h);
  std::vector< double > t(f->n);
  solveInto(f, first, t.data( ), contiguous(in, f->n, inName));
  solveInto(f, second, output(out, f->n, outName), t.data( ));
  return 0;
}
long forward(const long &h, KN< double > *const &y, KN< double > *const &b) {
  return twoSystems(h, y, b, CHOLMOD_P, CHOLMOD_L, "y", "b");
}
long backward(const long &h, KN< double > *const &x, KN< double > *const &y) {
  return twoSystems(h, x, y, CHOLMOD_DLt, CHOLMOD_Pt, "x", "y");
}

// W_k = L^-1 P e_d for the given dofs, solved in blocks of right-hand sides and kept sparse (the entries of a
// forward solve of e_d outside the path from d to the root of L's elimination tree are exact zeros). Every block
// has the same number of columns (zero columns fill the last), so a column's bits do not depend on which
// others were solved with it.
long addColumns(const long &h, KN< long > *const &dofs) {
  ColumnFactor *f = factorOf(h);
  const long first = f->index.size( ), m = dofs->N( ), block = 8;
  std::vector< double > B, X(f->n * block);     // (X: each solve writes it whole)
  for (long k0 = 0; k0 < m; k0 += block) {
    long nb = std::min(block, m - k0);
    B.assign(f->n * block, 0.);
    for (long k = 0; k < nb; ++k) {
      long d = (*dofs)[k0 + k];
      if (d < 0 || d >= f->n) ExecError("cholmod_columns: a dof is out of range");
      B[k * f->n + d] = 1;
    }
    solveInto(f, CHOLMOD_P, X.data( ), B.data( ), block);
    solveInto(f, CHOLMOD_L, B.data( ), X.data( ), block);
    for (long k = 0; k < nb; ++k) {
      std::vector< int > I;
      std::vector< double > V;
      const double *col = B.data( ) + k * f->n;
      for (long i = 0; i < f->n; ++i)
        if (col[i] != 0) {
          I.push_back(i);
          V.push_back(col[i]);
        }
      f->entries += I.size( );
      f->index.push_back(std::move(I));
      f->value.push_back(std::move(V));
    }
  }
  return first;
}

void checkColumn(ColumnFactor *f, long k) {
  if (k < 0 || k >= (long)f->index.size( )) ExecError("cholmod_columns: no such column");
}

long columnDots(const long &h, KN< long > *const &cols, KN< double > *const &y, KN< double > *const &out) {
  ColumnFactor *f = factorOf(h);
  const double *py = contiguous(y, f->n, "y");
  if (out->N( ) != cols->N( )) ExecError("cholmod_columns: out and cols differ in size");
  for (long i = 0; i < cols->N( ); ++i) {
    long k = (*cols)[i];
    checkColumn(f, k);
    const std::vector< int > &I = f->index[k];
    const std::vector< double > &V = f->value[k];
    double s = 0;
    for (size_t p = 0; p < I.size( ); ++p) s += V[p] * f->dinv[I[p]] * py[I[p]];
    (*out)[i] = s;
  }
  return 0;
}

long columnAxpy(const long &h, KN< long > *const &cols, KN< double > *const &coef, KN< double > *const &y) {
  ColumnFactor *f = factorOf(h);
  double *py = contiguous(y, f->n, "y");
  if (coef->N( ) != cols->N( )) ExecError("cholmod_columns: coef and cols differ in size");
  for (long i = 0; i < cols->N( ); ++i) {
    long k = (*cols)[i];
    checkColumn(f, k);
    double a = (*coef)[i];
    if (a == 0) continue;
    const std::vector< int > &I = f->index[k];
    const std::vector< double > &V = f->value[k];
    for (size_t p = 0; p < I.size( ); ++p) py[I[p]] += a * V[p];
  }
  return 0;
}

long columnGram(const long &h, KN< long > *const &rows, const long &col, KN< double > *const &out) {
  ColumnFactor *f = factorOf(h);
  checkColumn(f, col);
  if (out->N( ) != rows->N( )) ExecError("cholmod_columns: out and rows differ in size");
  const std::vector< int > &J = f->index[col];
  const std::vector< double > &U = f->value[col];
  for (size_t p = 0; p < J.size( ); ++p) f->scatter[J[p]] = U[p] * f->dinv[J[p]];
  for (long i = 0; i < rows->N( ); ++i) {
    long k = (*rows)[i];
    checkColumn(f, k);
    const std::vector< int > &I = f->index[k];
    const std::vector< double > &V = f->value[k];
    double s = 0;
    for (size_t p = 0; p < I.size( ); ++p) s += V[p] * f->scatter[I[p]];
    (*out)[i] = s;
  }
  for (size_t p = 0; p < J.size( ); ++p) f->scatter[J[p]] = 0;
  return 0;
}

double columnEntries(const long &h) { return factorOf(h)->entries; }
double factorEntries(const long &h) { cholmod_factor *L = factorOf(h)->L;  return L->is_super ? (double)L->xsize : (double)L->nzmax; }
double refusedMiBOf(const long &which) { return refusedMiB[which == 0 ? 0 : 1]; }
double wallSeconds( ) { return std::chrono::duration< double >(std::chrono::steady_clock::now( ).time_since_epoch( )).count( ); }
}    // namespace

static void Load_Init( ) {
  Global.Add("cholmodFactor", "(", new OneOperator3_< long, Matrice_Creuse< double > *, string *, string * >(factorise));
  Global.Add("cholmodSolve", "(", new OneOperator3_< long, long, KN< double > *, KN< double > * >(solveFull));
  Global.Add("cholmodSolveMany", "(",
             new OneOperator4_< long, long, KN< double > *, KN< double > *, long >(solveMany));
  Global.Add("cholmodForward", "(", new OneOperator3_< long, long, KN< double > *, KN< double > * >(forward));
  Global.Add("cholmodBackward", "(", new OneOperator3_< long, long, KN< double > *, KN< double > * >(backward));
  Global.Add("cholmodAddColumns", "(", new OneOperator2_< long, long, KN< long > * >(addColumns));
  Global.Add("cholmodColumnDots", "(",
             new OneOperator4_< long, long, KN< long > *, KN< double > *, KN< double > * >(columnDots));
  Global.Add("cholmodColumnAxpy", "(",
             new OneOperator4_< long, long, KN< long > *, KN< double > *, KN< double > * >(columnAxpy));
  Global.Add("cholmodColumnGram", "(",
             new OneOperator4_< long, long, KN< long > *, long, KN< double > * >(columnGram));
  Global.Add("cholmodColumnEntries", "(", new OneOperator1_< double, long >(columnEntries));
  Global.Add("cholmodFactorEntries", "(", new OneOperator1_< double, long >(factorEntries));
  Global.Add("cholmodRefusedMiB", "(", new OneOperator1_< double, long >(refusedMiBOf));
  Global.Add("wallSeconds", "(", new OneOperator0< double >(wallSeconds));
}

LOADFUNC(Load_Init)
