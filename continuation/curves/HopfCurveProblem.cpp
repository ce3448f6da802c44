#include "continuation/curves/HopfCurveProblem.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace keller {

namespace {

using Complex = std::complex<double>;
const Complex kI(0.0, 1.0);

// Bordered solves that refine borders set from a guess (inverse iteration with the shift
// i omega: each multiplies the error by the ratio of the two eigenvalues nearest it).
constexpr int kBorderRefinements = 3;

// A deterministic generic vector (no special structure, no zero entries): borders where no
// better guess is known.
Vector generic_vector(int n) {
  Vector g(n);
  for (int i = 0; i < n; ++i) g[i] = std::sin(1.0 + 0.7 * i);
  return g;
}

}  // namespace

HopfCurveProblem::HopfCurveProblem(Problem& inner, const std::string& hopf_parameter, SparseLUOptions lu)
    : CurveProblem(inner, hopf_parameter, 2, "Hopf curve"),
      b_(ComplexVector::Zero(inner.size())),
      c_(ComplexVector::Zero(inner.size())),
      lu_(lu),
      fold_(inner.size(), lu) {}

Vector HopfCurveProblem::state(const Vector& u, double p1, double omega) const {
  return CurveProblem::state(u, p1, Vector::Constant(1, omega));
}

SparseMatrix HopfCurveProblem::real_form(const SparseMatrix& J, const SparseMatrix& B, double omega) const {
  // unknowns (Re v, Im v, Re g, Im g), equations (Re, Im of the first block row; Re, Im of c^H v = 1):
  //   [ J      omega B   Re b  -Im b ]
  //   [ -omega B   J     Im b   Re b ]
  //   [ Re c^T  Im c^T    0      0   ]
  //   [ -Im c^T Re c^T    0      0   ]
  const int n = n_;
  std::vector<Eigen::Triplet<double, int>> t;
  t.reserve(2 * static_cast<size_t>(J.nonZeros() + B.nonZeros()) + 8 * static_cast<size_t>(n));
  for (int j = 0; j < n; ++j) {
    for (SparseMatrix::InnerIterator it(J, j); it; ++it) {
      t.emplace_back(it.row(), j, it.value());
      t.emplace_back(n + it.row(), n + j, it.value());
    }
    for (SparseMatrix::InnerIterator it(B, j); it; ++it) {
      t.emplace_back(it.row(), n + j, omega * it.value());
      t.emplace_back(n + it.row(), j, -omega * it.value());
    }
  }
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, 2 * n, b_[i].real());
    t.emplace_back(n + i, 2 * n, b_[i].imag());
    t.emplace_back(i, 2 * n + 1, -b_[i].imag());
    t.emplace_back(n + i, 2 * n + 1, b_[i].real());
    t.emplace_back(2 * n, i, c_[i].real());
    t.emplace_back(2 * n, n + i, c_[i].imag());
    t.emplace_back(2 * n + 1, i, -c_[i].imag());
    t.emplace_back(2 * n + 1, n + i, c_[i].real());
  }
  t.emplace_back(2 * n, 2 * n, 0.0);
  t.emplace_back(2 * n + 1, 2 * n + 1, 0.0);
  SparseMatrix M(2 * n + 2, 2 * n + 2);
  M.setFromTriplets(t.begin(), t.end());
  M.makeCompressed();
  return M;
}

Status HopfCurveProblem::analyse(const Vector& U) {
  Status st = set_p1(U);
  if (!st.is_ok()) return st;
  const double omega = U[n_ + 1];
  if (!std::isfinite(omega)) return {StatusCode::NotFinite, "Hopf curve: omega is not finite"};
  if (analysed_at(U)) return analysed_status_;
  analysed_status_ = [&]() -> Status {
    const Vector u = U.head(n_);
    Status s = inner_.jacobian(u, F_, J_);
    if (s.is_ok()) s = inner_.mass_matrix(u, B_);
    if (s.is_ok()) s = lu_.factorize(real_form(J_, B_, omega));
    if (!s.is_ok()) return s;
    const int n = n_;
    Vector rhs = Vector::Zero(2 * n + 2), x, y;
    rhs[2 * n] = 1.0;
    s = lu_.solve(rhs, x);
    if (s.is_ok()) s = lu_.solve(rhs, y, true);
    if (!s.is_ok()) return s;
    v_ = x.head(n).cast<Complex>() + kI * x.segment(n, n).cast<Complex>();
    g_ = Complex(x[2 * n], x[2 * n + 1]);
    w_ = y.head(n).cast<Complex>() + kI * y.segment(n, n).cast<Complex>();
    if (!v_.allFinite() || !w_.allFinite() || !std::isfinite(g_.real()) || !std::isfinite(g_.imag()))
      return {StatusCode::NotFinite, "Hopf curve: the bordered solve for the test function is not finite"};
    return {};
  }();
  return analysed_status_;
}

Status HopfCurveProblem::residual(const Vector& U, Vector& F) {
  Status st = analyse(U);
  if (!st.is_ok()) return st;
  F.resize(n_ + 2);
  F.head(n_) = F_;
  F[n_] = g_.real();
  F[n_ + 1] = g_.imag();
  return {};
}

Status HopfCurveProblem::parameter_term(int p, const Vector& u, double omega, Complex& gp) {
  // (J - i omega B)_p v = F_pu Re v + i F_pu Im v - i omega B_p v
  Vector Dr, Di;
  Status st = parameter_derivative_along(p, u, v_.real(), Dr);
  if (st.is_ok()) st = parameter_derivative_along(p, u, v_.imag(), Di);
  // w^H B_p v by central differences of w^H B v in p (B may depend on the parameters)
  Vector wBv_p;
  if (st.is_ok())
    st = parameter_difference(
        p,
        [&](Vector& value) {
          SparseMatrix B;
          const Status s = inner_.mass_matrix(u, B);
          const Complex wBv = w_.dot(B.cast<Complex>() * v_);
          value.resize(2);
          value << wBv.real(), wBv.imag();
          return s;
        },
        wBv_p);
  if (!st.is_ok()) return st;
  const ComplexVector Jp_v = Dr.cast<Complex>() + kI * Di.cast<Complex>();
  gp = -w_.dot(Jp_v) + kI * omega * Complex(wBv_p[0], wBv_p[1]);
  return {};
}

Status HopfCurveProblem::bordered_jacobian(const Vector& U, Vector& F, BorderedJacobian& J) {
  Status st = residual(U, F);
  if (!st.is_ok()) return st;
  const Vector u = U.head(n_);
  const double omega = U[n_ + 1];
  if (J.border_size() != 2 || J.inner_size() != n_) J = blocks();
  J.K = J_;
  // g_u = -(D_{Re v} J + i D_{Im v} J)^T conj(w) (F_uu symmetric in its two arguments)
  SparseMatrix Dr, Di;
  st = jacobian_along(u, v_.real(), Dr);
  if (st.is_ok()) st = jacobian_along(u, v_.imag(), Di);
  Vector Fp1;
  if (st.is_ok()) st = inner_.parameter_derivative(p1(), u, Fp1);
  Complex gp1;
  if (st.is_ok()) st = parameter_term(p1(), u, omega, gp1);
  if (!st.is_ok()) return st;
  const Vector wr = w_.real(), wi = w_.imag();
  J.B.col(0) = Fp1;
  J.B.col(1).setZero();
  J.C.col(0) = -(Dr.transpose() * wr + Di.transpose() * wi);
  J.C.col(1) = -(Di.transpose() * wr - Dr.transpose() * wi);
  // g_omega = i w^H B v
  const Complex gw = kI * w_.dot(B_.cast<Complex>() * v_);
  J.D << gp1.real(), gw.real(), gp1.imag(), gw.imag();
  return {};
}

Status HopfCurveProblem::equations_parameter_derivative(int p, const Vector& U, Vector& d) {
  Complex gp;
  Status st = analyse(U);
  if (st.is_ok()) st = parameter_term(p, U.head(n_), U[n_ + 1], gp);
  d.resize(2);
  d << gp.real(), gp.imag();
  return st;
}

Status HopfCurveProblem::null_vectors(const Vector& U, ComplexVector& v, ComplexVector& w, Complex& g) {
  Status st = analyse(U);
  if (!st.is_ok()) return st;
  v = v_;
  w = w_;
  g = g_;
  return {};
}

Status HopfCurveProblem::update_borders(const Vector& U) {
  Status st = analyse(U);
  if (!st.is_ok()) return st;
  const double vn = v_.norm(), wn = w_.norm();
  if (!(vn > 0.0) || !(wn > 0.0)) return {StatusCode::SingularMatrix, "Hopf curve: a null vector vanished"};
  c_ = v_ / vn;
  b_ = w_ / wn;
  st = fold_.evaluate(J_);
  if (st.is_ok()) st = fold_.update_borders();
  forget_analysis();  // the borders changed: g and the null vectors with them
  return st;
}

Status HopfCurveProblem::set_borders(const Vector& U, const ComplexVector& mode_guess) {
  if (mode_guess.size() && mode_guess.size() != n_)
    throw std::invalid_argument("Hopf curve: eigenvector guess of the wrong size");
  const ComplexVector guess =
      mode_guess.size() && mode_guess.norm() > 0
          ? mode_guess
          : ComplexVector(generic_vector(n_).cast<Complex>() + kI * generic_vector(n_).reverse());
  c_ = guess / guess.norm();
  b_ = c_;
  fold_.set_borders(generic_vector(n_));
  forget_analysis();
  for (int k = 0; k < kBorderRefinements; ++k) {
    Status st = update_borders(U);
    if (!st.is_ok()) return st;
  }
  return {};
}

Status HopfCurveProblem::start(Vector& U, const ComplexVector& mode_guess, const NewtonOptions& newton,
                               SparseLUOptions lu) {
  Status st = set_borders(U, mode_guess);
  if (!st.is_ok()) return st;
  const FixedParameterResult r = solve_here(U, newton, lu);
  if (!r.status.is_ok())
    return {StatusCode::NotConverged,
            "Hopf curve: Newton from the located Hopf point did not converge (" + r.status.describe() + ")"};
  return update_borders(U);
}

Status HopfCurveProblem::observables(const Vector& U, std::vector<double>& values) {
  Status st = analyse(U);
  if (!st.is_ok()) return st;
  st = inner_.observables(U.head(n_), values);
  if (!st.is_ok()) return st;
  values.push_back(U[n_]);
  values.push_back(U[n_ + 1]);
  return {};
}

std::vector<std::string> HopfCurveProblem::monitor_names() const {
  std::vector<std::string> names = inner_.monitor_names();
  names.push_back("bogdanov-takens");
  names.push_back("fold-hopf");
  if (l1_) names.push_back("bautin");
  return names;
}

std::vector<int> HopfCurveProblem::partial_monitors() const {
  if (!l1_) return {};
  return {static_cast<int>(monitor_names().size()) - 1};
}

Status HopfCurveProblem::monitors(const Vector& U, std::vector<double>& values) {
  Status st = analyse(U);
  if (!st.is_ok()) return st;
  st = inner_.monitors(U.head(n_), values);
  if (st.is_ok()) st = fold_.evaluate(J_);
  if (!st.is_ok()) return st;
  values.push_back(U[n_ + 1]);
  values.push_back(fold_.signed_g());
  if (l1_) {
    double l1 = NAN;
    // the normal form moves p1 and restores it: the analysis at U stays valid. Where it cannot be
    // computed (omega near zero at a Bogdanov-Takens point) the column is NaN and no zero is sought.
    if (!l1_(inner_, p1(), U.head(n_), U[n_ + 1], v_, l1).is_ok() || !std::isfinite(l1)) l1 = NAN;
    values.push_back(l1);
  }
  return {};
}

std::string HopfCurveProblem::summary() const {
  return fmt::format("Hopf curve (minimally augmented, unknowns the state, {} and omega) of {}", p1_name(),
                     inner_.summary());
}

}  // namespace keller
