#include "continuation/BorderedSystem.hpp"

#include <cmath>
#include <stdexcept>

namespace keller {

namespace {
// A Schur complement d - c.J^-1 b below this fraction of its terms is rounding: J is singular to
// working precision (a fold itself) and block elimination cannot be used.
constexpr double kVanishingSchur = 1e-12;
// Block elimination is accepted where iterative refinement brings the whole bordered system's
// residual below this fraction of its scale (near a singular J it loses accuracy) ...
constexpr double kRefinedResidual = 1e-10;
// ... within this many refinement steps; else the whole matrix is factorised.
constexpr int kRefinementSteps = 3;
}  // namespace

BorderedSystem::BorderedSystem(const SparseMatrix& P, SparseLUOptions options, Mode mode)
    : n_(static_cast<int>(P.rows())),
      nnz_j_(P.nonZeros()),
      mode_(mode),
      lu_(options),
      own_j_(std::make_shared<SparseLU>(options)),
      lu_j_(own_j_) {
  if (P.rows() != P.cols() || !P.isCompressed())
    throw std::invalid_argument("BorderedSystem: square compressed pattern");
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
  if (mode_ == Mode::Block) {
    J_ = J;
    b_ = b;
    c_ = c.size() ? c : Vector::Zero(n);
    d_ = d;
  }
}

Status BorderedSystem::adopt(std::shared_ptr<SparseLU> lu, const SparseMatrix& J, const Vector& b, const Vector& c,
                             double d) {
  if (mode_ != Mode::Block) return {StatusCode::InvalidState, "full bordered mode: nothing to adopt"};
  if (!lu || !lu->factorized()) return {StatusCode::InvalidState, "no factorisation to adopt"};
  set(J, b, c, d);
  release_adopted();
  lu_j_ = std::move(lu);
  adopted_base_ = lu_j_->statistics();
  block_ok_ = false;
  Status st = lu_j_->solve(b_, x2_);
  if (!st.is_ok()) return st;
  schur_ = d_ - c_.dot(x2_);
  const double scale = std::abs(d_) + c_.norm() * x2_.norm();
  if (!(std::isfinite(schur_) && std::abs(schur_) > kVanishingSchur * scale))
    return {StatusCode::SingularMatrix, "Schur complement of the adopted factorisation vanishes"};
  block_ok_ = true;
  return {};
}

void BorderedSystem::release_adopted() {
  if (lu_j_ == own_j_) return;
  adopted_solves_ += lu_j_->statistics().solves - adopted_base_.solves;
  adopted_solve_seconds_ += lu_j_->statistics().solve_seconds - adopted_base_.solve_seconds;
  lu_j_ = own_j_;
}

BorderedSystem::Totals BorderedSystem::totals() const {
  Totals t;
  const SparseLU::Statistics& f = lu_.statistics();
  const SparseLU::Statistics& o = own_j_->statistics();
  t.factorisations = f.factorisations + o.factorisations;
  t.factor_seconds = f.factor_seconds + o.factor_seconds;
  t.solves = f.solves + o.solves + adopted_solves_;
  t.solve_seconds = f.solve_seconds + o.solve_seconds + adopted_solve_seconds_;
  if (lu_j_ != own_j_) {
    t.solves += lu_j_->statistics().solves - adopted_base_.solves;
    t.solve_seconds += lu_j_->statistics().solve_seconds - adopted_base_.solve_seconds;
  }
  return t;
}

Status BorderedSystem::factorize() {
  block_ok_ = false;
  release_adopted();  // (an adopted factorisation belongs to its maker: ours is refactorised)
  if (mode_ == Mode::Block) {
    Status st = lu_j_->factorize(J_);
    if (st.is_ok()) st = lu_j_->solve(b_, x2_);
    if (st.is_ok()) {
      schur_ = d_ - c_.dot(x2_);
      const double scale = std::abs(d_) + c_.norm() * x2_.norm();
      if (std::isfinite(schur_) && std::abs(schur_) > kVanishingSchur * scale) {
        block_ok_ = true;
        return {};
      }
    }
    ++fallbacks_;
  }
  return lu_.factorize(A_);
}

int BorderedSystem::determinant_sign() const {
  if (block_ok_) return lu_j_->determinant_sign() * (schur_ > 0 ? 1 : -1);
  return lu_.determinant_sign();
}

Status BorderedSystem::set_row(const Vector& c, double d) {
  const int n = n_;
  if (c.size() && c.size() != n) throw std::invalid_argument("BorderedSystem::set_row: size mismatch");
  double* v = A_.valuePtr();
  const int* ao = A_.outerIndexPtr();
  for (int j = 0; j < n; ++j) v[ao[j + 1] - 1] = c.size() ? c[j] : 0.0;  // (n, j) closes column j
  v[A_.nonZeros() - 1] = d;
  if (mode_ != Mode::Block)
    return {StatusCode::InvalidState, "full bordered mode: the row is part of the factorisation"};
  c_ = c.size() ? c : Vector::Zero(n);
  d_ = d;
  if (!block_ok_) return {StatusCode::InvalidState, "no block factorisation to reuse"};
  schur_ = d_ - c_.dot(x2_);
  const double scale = std::abs(d_) + c_.norm() * x2_.norm();
  if (!(std::isfinite(schur_) && std::abs(schur_) > kVanishingSchur * scale)) {
    block_ok_ = false;
    return {StatusCode::SingularMatrix, "Schur complement of the new border row vanishes"};
  }
  return {};
}

Status BorderedSystem::solve_block(const Vector& f, double g, Vector& x, double& y) {
  Vector x1;
  Status st = lu_j_->solve(f, x1, false, 0);  // plain: the whole bordered system is refined below
  if (!st.is_ok()) return st;
  y = (g - c_.dot(x1)) / schur_;
  x = x1 - y * x2_;
  return {};
}

Status BorderedSystem::solve(const Vector& f, double g, Vector& x, double& y, bool refine) {
  if (block_ok_) {
    Status st = solve_block(f, g, x, y);
    if (!st.is_ok()) return st;
    if (!refine) return x.allFinite() && std::isfinite(y) ? Status{} : Status{StatusCode::NotFinite, "bordered solve"};
    // iterative refinement on the whole bordered system: near a singular J block elimination
    // loses accuracy; if refinement does not restore it, fall back to the whole matrix
    const double scale_ab = std::abs(d_) + c_.cwiseAbs().maxCoeff() + b_.cwiseAbs().maxCoeff();
    const double scale_f = f.cwiseAbs().maxCoeff() + std::abs(g);
    for (int step = 0; step <= kRefinementSteps; ++step) {
      if (!x.allFinite() || !std::isfinite(y)) break;
      const Vector rf = f - J_ * x - b_ * y;
      const double rg = g - c_.dot(x) - d_ * y;
      const double res = rf.cwiseAbs().maxCoeff() + std::abs(rg);
      const double scale = scale_f + scale_ab * (x.cwiseAbs().maxCoeff() + std::abs(y));
      if (res <= kRefinedResidual * scale) return {};
      if (step == kRefinementSteps) break;
      Vector dx;
      double dy = 0;
      st = solve_block(rf, rg, dx, dy);
      if (!st.is_ok()) return st;
      x += dx;
      y += dy;
    }
    block_ok_ = false;
    ++fallbacks_;
    st = lu_.factorize(A_);
    if (!st.is_ok()) return st;
  }
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
