#include "continuation/BorderedSystem.hpp"

#include <stdexcept>

namespace keller {

BorderedSystem::BorderedSystem(const SparseMatrix& P, SparseLUOptions options)
    : n_(static_cast<int>(P.rows())), nnz_j_(P.nonZeros()), lu_(options) {
  if (P.rows() != P.cols() || !P.isCompressed()) throw std::invalid_argument("BorderedSystem: square compressed pattern");
  // column j < n: J's entries then (n, j); column n: rows 0..n
  const int n = n_;
  A_.resize(n + 1, n + 1);
  A_.resizeNonZeros(nnz_j_ + n + (n + 1));
  int* outer = A_.outerIndexPtr();
  int* inner = A_.innerIndexPtr();
  long k = 0;
  for (int j = 0; j < n; ++j) {
    outer[j] = static_cast<int>(k);
    for (int p = P.outerIndexPtr()[j]; p < P.outerIndexPtr()[j + 1]; ++p) inner[k++] = P.innerIndexPtr()[p];
    inner[k++] = n;
  }
  outer[n] = static_cast<int>(k);
  for (int i = 0; i <= n; ++i) inner[k++] = i;
  outer[n + 1] = static_cast<int>(k);
  std::fill(A_.valuePtr(), A_.valuePtr() + A_.nonZeros(), 0.0);
}

void BorderedSystem::set(const SparseMatrix& J, const Vector& b, const Vector& c, double d) {
  if (J.nonZeros() != nnz_j_) throw std::invalid_argument("BorderedSystem::set: J has a different pattern");
  const int n = n_;
  double* v = A_.valuePtr();
  const double* jv = J.valuePtr();
  const int* jo = J.outerIndexPtr();
  for (int j = 0; j < n; ++j) {
    const long base = jo[j] + j;  // every earlier column gained one entry
    const int len = jo[j + 1] - jo[j];
    for (int p = 0; p < len; ++p) v[base + p] = jv[jo[j] + p];
    v[base + len] = c.size() ? c[j] : 0.0;
  }
  const long last = nnz_j_ + n;
  for (int i = 0; i < n; ++i) v[last + i] = b[i];
  v[last + n] = d;
}

Status BorderedSystem::factorize() { return lu_.factorize(A_); }

Status BorderedSystem::solve(const Vector& f, double g, Vector& x, double& y) {
  Vector rhs(n_ + 1), sol;
  rhs.head(n_) = f;
  rhs[n_] = g;
  Status st = lu_.solve(rhs, sol);
  if (!st.is_ok()) return st;
  x = sol.head(n_);
  y = sol[n_];
  return {};
}

}  // namespace keller
