#include "continuation/engine/BorderedSystem.hpp"

#include <Eigen/SVD>
#include <cmath>
#include <stdexcept>

namespace keller {

namespace {
// A Schur complement whose smallest singular value is below this fraction of its terms is
// rounding: the inner matrix is singular to working precision (a fold itself) and block
// elimination cannot be used.
constexpr double kVanishingSchur = 1e-12;
// Block elimination is accepted where iterative refinement brings the whole bordered system's
// residual below this fraction of its scale (near a singular J it loses accuracy) ...
constexpr double kRefinedResidual = 1e-10;
// ... within this many refinement steps; else the whole matrix is factorised.
constexpr int kRefinementSteps = 3;

double max_abs(const Matrix& M) { return M.size() ? M.cwiseAbs().maxCoeff() : 0.0; }
}  // namespace

BorderedSystem::BorderedSystem(const SparseMatrix& P, int borders, SparseLUOptions options, Mode mode)
    : nk_(static_cast<int>(P.rows())),
      m_(borders),
      n_(nk_ + borders),
      nnz_k_(P.nonZeros()),
      mode_(mode),
      lu_(options),
      K_(P),
      Bt_(Matrix::Zero(nk_, borders + 1)),
      Ct_(Matrix::Zero(nk_, borders + 1)),
      Dt_(Matrix::Zero(borders + 1, borders + 1)),
      own_j_(std::make_shared<SparseLU>(options)),
      lu_j_(own_j_) {
  if (P.rows() != P.cols() || !P.isCompressed())
    throw std::invalid_argument("BorderedSystem: square compressed pattern");
  if (borders < 0) throw std::invalid_argument("BorderedSystem: a negative number of borders");
  // column j < nk: K's entries then rows nk..nk+k-1 (the border rows); columns nk..N: every row
  const int nk = nk_, k = m_ + 1;
  A_.resize(n_ + 1, n_ + 1);
  A_.resizeNonZeros(nnz_k_ + static_cast<long>(nk) * k + static_cast<long>(k) * (n_ + 1));
  int* outer = A_.outerIndexPtr();
  int* inner = A_.innerIndexPtr();
  long p = 0;
  for (int j = 0; j < nk; ++j) {
    outer[j] = static_cast<int>(p);
    for (int q = P.outerIndexPtr()[j]; q < P.outerIndexPtr()[j + 1]; ++q) inner[p++] = P.innerIndexPtr()[q];
    for (int b = 0; b < k; ++b) inner[p++] = nk + b;
  }
  for (int b = 0; b < k; ++b) {
    outer[nk + b] = static_cast<int>(p);
    for (int i = 0; i <= n_; ++i) inner[p++] = i;
  }
  outer[n_ + 1] = static_cast<int>(p);
  std::fill(A_.valuePtr(), A_.valuePtr() + A_.nonZeros(), 0.0);
}

void BorderedSystem::fill() {
  const int nk = nk_, k = m_ + 1;
  double* v = A_.valuePtr();
  const double* kv = K_.valuePtr();
  const int* ko = K_.outerIndexPtr();
  long p = 0;
  for (int j = 0; j < nk; ++j) {
    for (int q = ko[j]; q < ko[j + 1]; ++q) v[p++] = kv[q];
    for (int b = 0; b < k; ++b) v[p++] = Ct_(j, b);
  }
  for (int b = 0; b < k; ++b) {
    for (int i = 0; i < nk; ++i) v[p++] = Bt_(i, b);
    for (int i = 0; i < k; ++i) v[p++] = Dt_(i, b);
  }
}

void BorderedSystem::set(const SparseMatrix& J, const Vector& b, const Vector& c, double d) {
  if (m_ != 0) throw std::invalid_argument("BorderedSystem::set: the problem has a border; J in bordered form");
  if (J.nonZeros() != nnz_k_) throw std::invalid_argument("BorderedSystem::set: J has a different pattern");
  K_ = J;
  Bt_.col(0) = b;
  if (c.size())
    Ct_.col(0) = c;
  else
    Ct_.col(0).setZero();
  Dt_(0, 0) = d;
  fill();
}

void BorderedSystem::set(const BorderedJacobian& J, const Vector& b, const Vector& c, double d) {
  if (J.border_size() != m_ || J.inner_size() != nk_ || J.K.nonZeros() != nnz_k_)
    throw std::invalid_argument("BorderedSystem::set: the bordered Jacobian has a different structure");
  const int m = m_, nk = nk_;
  K_ = J.K;
  Bt_.leftCols(m) = J.B;
  Bt_.col(m) = b.head(nk);
  Ct_.leftCols(m) = J.C;
  Dt_.topLeftCorner(m, m) = J.D;
  Dt_.col(m).head(m) = b.tail(m);
  set_last_row(c, d);
  fill();
}

void BorderedSystem::set_last_row(const Vector& c, double d) {
  const int nk = nk_, m = m_;
  if (c.size()) {
    Ct_.col(m) = c.head(nk);
    Dt_.row(m).head(m) = c.tail(m).transpose();
  } else {
    Ct_.col(m).setZero();
    Dt_.row(m).head(m).setZero();
  }
  Dt_(m, m) = d;
}

bool BorderedSystem::schur() {
  S_ = Dt_ - Ct_.transpose() * X_;
  const double scale = Dt_.norm() + Ct_.norm() * X_.norm();
  if (!S_.allFinite()) return false;
  const Vector sv = Eigen::JacobiSVD<Matrix>(S_).singularValues();
  if (!(sv[sv.size() - 1] > kVanishingSchur * scale)) return false;
  S_lu_.compute(S_);
  return true;
}

Status BorderedSystem::adopt(std::shared_ptr<SparseLU> lu, const SparseMatrix& J, const Vector& b, const Vector& c,
                             double d) {
  if (mode_ != Mode::Block) return {StatusCode::InvalidState, "full bordered mode: nothing to adopt"};
  if (m_ != 0) return {StatusCode::InvalidState, "the problem has a border: J's factorisation is not its inner one"};
  if (!lu || !lu->factorized()) return {StatusCode::InvalidState, "no factorisation to adopt"};
  set(J, b, c, d);
  return adopt_inner(std::move(lu));
}

Status BorderedSystem::adopt(std::shared_ptr<SparseLU> lu, const BorderedJacobian& J, const Vector& b, const Vector& c,
                             double d) {
  if (mode_ != Mode::Block) return {StatusCode::InvalidState, "full bordered mode: nothing to adopt"};
  if (!lu || !lu->factorized()) return {StatusCode::InvalidState, "no factorisation to adopt"};
  set(J, b, c, d);
  return adopt_inner(std::move(lu));
}

Status BorderedSystem::adopt_inner(std::shared_ptr<SparseLU> lu) {
  release_adopted();
  if (lu != own_j_) {
    lu_j_ = std::move(lu);
    adopted_base_ = lu_j_->statistics();
  }
  block_ok_ = false;
  const Status st = solve_borders();
  if (!st.is_ok()) return st;
  if (!schur()) return {StatusCode::SingularMatrix, "Schur complement of the adopted factorisation vanishes"};
  block_ok_ = true;
  return {};
}

void BorderedSystem::release_adopted(bool take_over) {
  if (lu_j_ == own_j_) return;
  adopted_solves_ += lu_j_->statistics().solves - adopted_base_.solves;
  adopted_solve_seconds_ += lu_j_->statistics().solve_seconds - adopted_base_.solve_seconds;
  if (take_over) {
    // (our own factorisations and solves so far kept in the adopted counts)
    const SparseLU::Statistics& o = own_j_->statistics();
    earlier_own_factorisations_ += o.factorisations - own_base_.factorisations;
    earlier_own_factor_seconds_ += o.factor_seconds - own_base_.factor_seconds;
    adopted_solves_ += o.solves - own_base_.solves;
    adopted_solve_seconds_ += o.solve_seconds - own_base_.solve_seconds;
    own_j_ = lu_j_;
    own_base_ = own_j_->statistics();
  }
  lu_j_ = own_j_;
}

BorderedSystem::Totals BorderedSystem::totals() const {
  Totals t;
  const SparseLU::Statistics& f = lu_.statistics();
  const SparseLU::Statistics& o = own_j_->statistics();
  t.factorisations = f.factorisations + o.factorisations - own_base_.factorisations + earlier_own_factorisations_;
  t.factor_seconds = f.factor_seconds + o.factor_seconds - own_base_.factor_seconds + earlier_own_factor_seconds_;
  t.solves = f.solves + o.solves - own_base_.solves + adopted_solves_;
  t.solve_seconds = f.solve_seconds + o.solve_seconds - own_base_.solve_seconds + adopted_solve_seconds_;
  if (lu_j_ != own_j_) {
    t.solves += lu_j_->statistics().solves - adopted_base_.solves;
    t.solve_seconds += lu_j_->statistics().solve_seconds - adopted_base_.solve_seconds;
  }
  return t;
}

Status BorderedSystem::factorize() {
  block_ok_ = false;
  // an adopted factorisation belongs to its maker, and ours is refactorised; but one its maker has
  // let go of (we hold the only reference) is refactorised as ours, with the symbolic analysis it
  // has (a new one costs a third of a numeric factorisation on M2)
  const bool take_over = lu_j_ != own_j_ && lu_j_.use_count() == 1;
  release_adopted(take_over);
  if (mode_ == Mode::Block) {
    Status st = lu_j_->factorize(K_);
    if (st.is_ok()) st = solve_borders();
    if (st.is_ok() && schur()) {
      block_ok_ = true;
      return {};
    }
    ++fallbacks_;
  }
  return lu_.factorize(A_);
}

int BorderedSystem::determinant_sign() const {
  if (block_ok_) return lu_j_->determinant_sign() * (S_lu_.determinant() > 0 ? 1 : -1);
  return lu_.determinant_sign();
}

Status BorderedSystem::set_row(const Vector& c, double d) {
  const int nk = nk_, m = m_;
  if (c.size() && c.size() != n_) throw std::invalid_argument("BorderedSystem::set_row: size mismatch");
  set_last_row(c, d);
  // in A_: the last entry of each inner column, and row N of each border column
  double* v = A_.valuePtr();
  const int* ao = A_.outerIndexPtr();
  for (int j = 0; j < nk; ++j) v[ao[j + 1] - 1] = Ct_(j, m);
  for (int b = 0; b <= m; ++b) v[ao[nk + b + 1] - 1] = Dt_(m, b);
  if (mode_ != Mode::Block)
    return {StatusCode::InvalidState, "full bordered mode: the row is part of the factorisation"};
  if (!block_ok_) return {StatusCode::InvalidState, "no block factorisation to reuse"};
  if (!schur()) {
    block_ok_ = false;
    return {StatusCode::SingularMatrix, "Schur complement of the new border row vanishes"};
  }
  return {};
}

Status BorderedSystem::solve_borders() {
  // Plain solves, like solve_block's own: the chord's iterations and the refinement of the whole
  // bordered system (solve) correct what they leave, which is little (MUMPS's plain solves leave a
  // backward error of 1e-13 to 1e-11 on the flow matrices; refined, each cost two solves).
  X_.resize(nk_, m_ + 1);
  for (int b = 0; b <= m_; ++b) {
    Vector x;
    const Status st = lu_j_->solve(Bt_.col(b), x, false, 0);
    if (!st.is_ok()) return st;
    X_.col(b) = x;
  }
  return {};
}

Status BorderedSystem::solve_block(const Vector& f, double g, Vector& x, double& y) {
  const int nk = nk_, m = m_;
  Vector x1;
  Status st = lu_j_->solve(f.head(nk), x1, false, 0);  // plain: the whole bordered system is refined below
  if (!st.is_ok()) return st;
  Vector rhs(m + 1);
  rhs.head(m) = f.tail(m);
  rhs[m] = g;
  const Vector z = S_lu_.solve(rhs - Ct_.transpose() * x1);
  x.resize(n_);
  x.head(nk) = x1 - X_ * z;
  x.tail(m) = z.head(m);
  y = z[m];
  return {};
}

Status BorderedSystem::solve(const Vector& f, double g, Vector& x, double& y, bool refine) {
  if (block_ok_) {
    Status st = solve_block(f, g, x, y);
    if (!st.is_ok()) return st;
    if (!refine) return x.allFinite() && std::isfinite(y) ? Status{} : Status{StatusCode::NotFinite, "bordered solve"};
    // iterative refinement on the whole bordered system: near a singular J block elimination
    // loses accuracy; if refinement does not restore it, fall back to the whole matrix
    const int nk = nk_, m = m_;
    const double scale_ab = max_abs(Dt_) + max_abs(Ct_) + max_abs(Bt_);
    const double scale_f = f.cwiseAbs().maxCoeff() + std::abs(g);
    Vector z(m + 1), rhs(m + 1);
    rhs.head(m) = f.tail(m);
    rhs[m] = g;
    for (int step = 0; step <= kRefinementSteps; ++step) {
      if (!x.allFinite() || !std::isfinite(y)) break;
      z.head(m) = x.tail(m);
      z[m] = y;
      Vector r(n_);
      r.head(nk) = f.head(nk) - K_ * x.head(nk) - Bt_ * z;
      const Vector rb = rhs - Ct_.transpose() * x.head(nk) - Dt_ * z;
      r.tail(m) = rb.head(m);
      const double rg = rb[m];
      const double res = r.cwiseAbs().maxCoeff() + std::abs(rg);
      const double scale = scale_f + scale_ab * (x.cwiseAbs().maxCoeff() + std::abs(y));
      if (res <= kRefinedResidual * scale) return {};
      if (step == kRefinementSteps) break;
      Vector dx;
      double dy = 0;
      st = solve_block(r, rg, dx, dy);
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
