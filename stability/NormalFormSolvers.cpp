#include "stability/NormalFormSolvers.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <Eigen/QR>

#include "core/Gmres.hpp"

namespace keller::normal_forms {

namespace {

// inverse iteration: until the direction changes by less than 1e-10, at most 100 solves on one
// factorisation
constexpr int kInverseIterations = 100;
constexpr double kInverseTolerance = 1e-10;
// at a Hopf point, from the stored eigenvector (accurate to the spectrum's tolerance): a few
constexpr int kHopfIterations = 20;
// on J's real factorisation: rounds of the bordered systems and the Rayleigh quotient until omega
// changes by less than this share of itself (the second round from a spectrum's eigenvector)
constexpr int kHopfRounds = 4;
constexpr double kHopfRoundTolerance = 1e-12;

// GMRES (core/Gmres.hpp): the iterations taken to converge, or -1
template <class Apply, class Precondition>
int gmres(const Apply& A, const Precondition& P, const ComplexVector& b, ComplexVector& x, double tol,
          int max_iterations) {
  const GmresResult r = keller::gmres(A, P, b, x, tol, max_iterations);
  return r.converged ? r.iterations : -1;
}

// out <- step(out), normalised, its sign kept (a negative eigenvalue flips it at every step),
// until the direction changes by less than kInverseTolerance
template <class Step>
Status inverse_iteration(Vector start, Vector& out, const Step& step) {
  out = start.normalized();
  Vector x;
  for (int k = 0; k < kInverseIterations; ++k) {
    if (Status st = step(out, x); !st.is_ok()) return st;
    x.normalize();
    if (x.dot(out) < 0) x = -x;
    const double change = (x - out).norm();
    out = x;
    if (change < kInverseTolerance) break;
  }
  return {};
}

// The start for q at a Hopf point: the guess or its conjugate, whichever J + i omega B nearly
// annuls, or a generic start
ComplexVector pick_guess(const SparseMatrix& J, const SparseMatrix& B, const Eigen::VectorXcd* guess, double omega) {
  const Complex I(0.0, 1.0);
  const int n = static_cast<int>(J.rows());
  if (!guess || guess->size() != n || !(guess->norm() > 0)) return generic_start(n).cast<Complex>();
  const ComplexVector g = guess->normalized(), gc = g.conjugate();
  const double rg = (times(J, g) + I * omega * times(B, g)).norm(),
               rc = (times(J, gc) + I * omega * times(B, gc)).norm();
  return rg <= rc ? g : gc;
}

}  // namespace

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Vector generic_start(int n) {
  Vector v(n);
  for (int i = 0; i < n; ++i) v[i] = 1.0 + 0.5 * std::sin(1.7 * i + 0.3);
  return v.normalized();
}

Status factorise(SparseLU& lu, const SparseMatrix& J, long& count) {
  ++count;
  Status st = lu.factorize(J);
  if (st.code() != StatusCode::SingularMatrix) return st;
  SparseMatrix shifted = J;
  const double scale = std::max(1.0, J.coeffs().cwiseAbs().maxCoeff());
  for (int i = 0; i < J.rows(); ++i) shifted.coeffRef(i, i) += 1e-12 * scale;
  ++count;
  return lu.factorize(shifted);
}

Status null_vector(SparseLU& lu, Vector start, bool transpose, Vector& out) {
  return inverse_iteration(std::move(start), out,
                           [&](const Vector& v, Vector& x) { return lu.solve(v, x, transpose); });
}

Status smallest_singular_vector(SparseLU& lu, Vector start, bool transpose, Vector& out) {
  Vector y;
  return inverse_iteration(std::move(start), out, [&](const Vector& v, Vector& x) {
    Status st = lu.solve(v, y, !transpose);
    return st.is_ok() ? lu.solve(y, x, transpose) : st;
  });
}

Status solve_bordered(SparseLU& lu, const Vector& phi, const Vector& psi, Vector rhs, Vector& out) {
  rhs -= psi.dot(rhs) * psi;
  Status st = lu.solve(rhs, out);
  if (!st.is_ok()) return st;
  out -= phi.dot(out) * phi;
  return {};
}

Status jacobian(Problem& problem, const Vector& u, SparseMatrix& J) {
  Vector F;
  J = problem.jacobian_pattern();
  return problem.jacobian(u, F, J);
}

Status jacobian_and_mass(Problem& problem, const Vector& u, SparseMatrix& J, SparseMatrix& B) {
  if (Status st = jacobian(problem, u, J); !st.is_ok()) return st;
  if (!has_time_form(problem, u)) {
    B.resize(u.size(), u.size());
    B.setIdentity();
    return {};
  }
  B = problem.jacobian_pattern();
  return problem.mass_matrix(u, B);
}

Status begin(Problem& problem, const Vector& u, NormalForm::Kind kind, const char* type, NormalForm& out,
             SparseMatrix& J, SparseMatrix& B) {
  out = {};
  out.kind = kind;
  out.type = type;
  return jacobian_and_mass(problem, u, J, B);
}

void record(const HigherDerivatives& d, NormalForm& out) {
  out.exact_derivatives = d.method() == HigherDerivatives::Method::Exact;
  out.derivatives = d.method_name();
  out.derivative_evaluations = d.evaluations();
  out.derivative_seconds = d.seconds();
}

ComplexVector times(const SparseMatrix& M, const ComplexVector& v) {
  return ComplexVector(M * v.real().eval() + Complex(0.0, 1.0) * (M * v.imag().eval()).cast<Complex>());
}

int DeflatedShiftSolver::solve(double s, const ComplexVector& b, ComplexVector& x) const {
  if (max_iterations_ <= 0) return -1;
  const Complex shift(0.0, s), on_q(0.0, s - omega_);
  auto A = [&](const ComplexVector& v) { return ComplexVector(times(J_, v) + shift * times(B_, v)); };
  Status failed;
  auto P = [&](const ComplexVector& v) {
    const Complex c = p_.dot(v);
    ComplexVector y;
    if (Status st = lu1_.solve(v - c * Bq_, y, false, 0); !st.is_ok()) {
      failed = st;
      return ComplexVector(ComplexVector::Zero(v.size()));
    }
    y -= Btp_.dot(y) * q_;
    return ComplexVector(y + (c / on_q) * q_);
  };
  const int iterations = gmres(A, P, b, x, kTolerance, max_iterations_);
  if (iterations < 0 || !failed.is_ok() || !((A(x) - b).norm() <= kCheck * b.norm())) return -1;
  return iterations;
}

ComplexVector RealLUShiftSolver::apply(double s, const ComplexVector& v, bool adjoint) const {
  const Complex shift(0.0, adjoint ? -s : s);
  return adjoint ? ComplexVector(times(Jt_, v) + shift * times(Bt_, v))
                 : ComplexVector(times(J_, v) + shift * times(B_, v));
}

ComplexVector RealLUShiftSolver::precondition(const ComplexVector& v, bool adjoint) const {
  Eigen::MatrixXd b(v.size(), 2), x;
  b.col(0) = v.real();
  b.col(1) = v.imag();
  if (Status st = lu_.solve_columns(b, x, adjoint); !st.is_ok()) {
    failed_ = st;
    return ComplexVector::Zero(v.size());
  }
  return x.col(0).cast<Complex>() + Complex(0.0, 1.0) * x.col(1).cast<Complex>();
}

int RealLUShiftSolver::solve(double s, const ComplexVector& b, ComplexVector& x, bool adjoint) const {
  if (max_iterations_ <= 0) return -1;
  failed_ = {};
  auto A = [&](const ComplexVector& v) { return apply(s, v, adjoint); };
  auto P = [&](const ComplexVector& v) { return precondition(v, adjoint); };
  const int iterations = gmres(A, P, b, x, kTolerance, max_iterations_);
  if (iterations < 0 || !failed_.is_ok() || !((A(x) - b).norm() <= kCheck * b.norm())) return -1;
  return iterations;
}

int RealLUShiftSolver::null_vector(double s, const ComplexVector& border, const ComplexVector& c, ComplexVector& x,
                                   bool adjoint) const {
  if (max_iterations_ <= 0) return -1;
  failed_ = {};
  const Eigen::Index n = J_.rows();
  // the bordered J's inverse: y1 = J^-1 f, mu = (c^H y1 - g) / (c^H J^-1 border), x = y1 - mu J^-1 border
  const ComplexVector y2 = precondition(border, adjoint);
  const Complex cy2 = c.dot(y2);
  if (!failed_.is_ok() || std::abs(cy2) == 0.0) return -1;
  auto A = [&](const ComplexVector& z) {
    ComplexVector out(n + 1);
    out.head(n) = apply(s, z.head(n), adjoint) + z[n] * border;
    out[n] = c.dot(z.head(n));
    return out;
  };
  auto P = [&](const ComplexVector& z) {
    const ComplexVector y1 = precondition(z.head(n), adjoint);
    const Complex mu = (c.dot(y1) - z[n]) / cy2;
    ComplexVector out(n + 1);
    out.head(n) = y1 - mu * y2;
    out[n] = mu;
    return out;
  };
  ComplexVector rhs = ComplexVector::Zero(n + 1), z;
  rhs[n] = 1.0;
  const int iterations = gmres(A, P, rhs, z, kTolerance, max_iterations_);
  if (iterations < 0 || !failed_.is_ok()) return -1;
  x = z.head(n);
  // the residual against the rounding of A x, eps |A| |x| (A x itself is small: x is nearly A's
  // null vector)
  const double scale = (norm_J_ + s * norm_B_) * x.norm() + std::abs(z[n]) * border.norm();
  if (!((apply(s, x, adjoint) + z[n] * border).norm() <= kCheck * scale) || !(std::abs(c.dot(x) - 1.0) <= kCheck))
    return -1;
  return iterations;
}

Status critical_pair_on_real_lu(const RealLUShiftSolver& solver, const SparseMatrix& J, const SparseMatrix& B,
                                const Eigen::VectorXcd* guess, double& omega, ComplexVector& q, ComplexVector& p,
                                int& iterations) {
  iterations = 0;
  ComplexVector start = pick_guess(J, B, guess, omega);
  for (int round = 0; round < kHopfRounds; ++round) {
    const ComplexVector c = start.normalized();
    const int it = solver.null_vector(omega, times(B, c), c, q, false);
    if (it < 0) {
      iterations = -1;
      return {};
    }
    q.normalize();
    // A^H's null vector: the border q is off A^H's range (q's orthogonal complement), and B q is
    // not orthogonal to p (p^H B q != 0 at a simple eigenvalue)
    const int ita = solver.null_vector(omega, q, times(B, q), p, true);
    if (ita < 0) {
      iterations = -1;
      return {};
    }
    iterations += it + ita;
    p.normalize();
    const Complex sigma = p.dot(times(J, q)) / p.dot(times(B, q));
    const double change = std::abs(-sigma.imag() - omega);
    omega = -sigma.imag();
    if (!(omega > 0.0))
      return {StatusCode::InvalidState,
              fmt::format("no complex pair near the Hopf point (sigma = {:.6g}{:+.6g}i)", sigma.real(), sigma.imag())};
    if (change <= kHopfRoundTolerance * omega) break;
    start = q;
  }
  return {};
}

Status critical_pair(const SparseMatrix& J, const SparseMatrix& B, ShiftedLU& lu1, const Eigen::VectorXcd* guess,
                     double& omega, ComplexVector& q, ComplexVector& p) {
  q = pick_guess(J, B, guess, omega);
  ComplexVector x;
  // inverse iteration of the pencil: x = (J + i s B)^-1 B v, and for the left vector x = (J + i s
  // B)^-H B^T v (without B^T it would converge to an eigenvector of (J + i s B)^H itself, which is
  // the pencil's left vector only where s is omega exactly); the phase of each iterate is fixed by
  // its inner product with the last
  const SparseMatrix Bt = B.transpose();
  auto iterate = [&](ComplexVector& v, bool adjoint) -> Status {
    for (int k = 0; k < kHopfIterations; ++k) {
      Status s = lu1.solve(adjoint ? times(Bt, v) : times(B, v), x, adjoint);
      if (!s.is_ok()) return s;
      x.normalize();
      const Complex overlap = v.dot(x);
      if (std::abs(overlap) > 0) x *= std::conj(overlap) / std::abs(overlap);
      const double change = (x - v).norm();
      v = x;
      if (change < kInverseTolerance) break;
    }
    return {};
  };
  if (Status st = iterate(q, false); !st.is_ok()) return st;
  p = times(B, q).normalized();
  if (Status st = iterate(p, true); !st.is_ok()) return st;
  const Complex sigma = p.dot(times(J, q)) / p.dot(times(B, q));
  omega = -sigma.imag();
  if (!(omega > 0.0))
    return {StatusCode::InvalidState,
            fmt::format("no complex pair near the Hopf point (sigma = {:.6g}{:+.6g}i)", sigma.real(), sigma.imag())};
  return {};
}

}  // namespace keller::normal_forms
