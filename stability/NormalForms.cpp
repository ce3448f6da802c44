#include "stability/NormalForms.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <vector>

#include <fmt/format.h>
#include <Eigen/QR>

#include "core/HigherDerivatives.hpp"

namespace keller {

namespace {

using Complex = std::complex<double>;
using ComplexVector = Eigen::VectorXcd;
using Direction = HigherDerivatives::Direction;
using ComplexDirection = HigherDerivatives::ComplexDirection;

// inverse iteration: until the direction changes by less than 1e-10, at most 100 solves on one
// factorisation (as the branch switcher's: slow modes near zero separate slowly)
constexpr int kInverseIterations = 100;
constexpr double kInverseTolerance = 1e-10;
// at a Hopf point, from the stored eigenvector (accurate to the spectrum's tolerance): a few
constexpr int kHopfIterations = 20;
// |psi1^T B q0| above this share of |B q0|: the zero is simple, no Bogdanov-Takens point (the
// located points on a Hopf curve have omega below 1e-4, and psi1^T B q0 of its order)
constexpr double kNotBogdanovTakens = 1e-3;
// a bifurcation-equation coefficient this small against the others is zero (a pitchfork's a)
constexpr double kZeroCoefficient = 1e-6;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// A start for inverse iteration with no guess: deterministic and in general position (not
// orthogonal to a symmetric or antisymmetric mode).
Vector generic_start(int n) {
  Vector v(n);
  for (int i = 0; i < n; ++i) v[i] = 1.0 + 0.5 * std::sin(1.7 * i + 0.3);
  return v.normalized();
}

// Factorises J; a matrix singular to working precision (a point located exactly) gets a shift of
// 1e-12 of its largest entry, which moves its null vectors by that much.
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

// J's null vector (transpose: its left null vector) by inverse iteration from `start`.
Status null_vector(SparseLU& lu, Vector start, bool transpose, Vector& out) {
  out = start.normalized();
  Vector x;
  for (int k = 0; k < kInverseIterations; ++k) {
    Status st = lu.solve(out, x, transpose);
    if (!st.is_ok()) return st;
    x.normalize();
    if (x.dot(out) < 0) x = -x;  // a negative eigenvalue flips the sign at every step
    const double change = (x - out).norm();
    out = x;
    if (change < kInverseTolerance) break;
  }
  return {};
}

// J's right (transpose: left) singular vector of its smallest singular value, by inverse iteration
// on J^T J (J J^T) from `start`: unlike inverse iteration on J it converges where the eigenvalues
// nearest zero are a complex pair or a Jordan block (a Bogdanov-Takens point, located where they
// are +-i omega with omega -> 0).
Status smallest_singular_vector(SparseLU& lu, Vector start, bool transpose, Vector& out) {
  out = start.normalized();
  Vector x, y;
  for (int k = 0; k < kInverseIterations; ++k) {
    Status st = lu.solve(out, y, !transpose);
    if (st.is_ok()) st = lu.solve(y, x, transpose);
    if (!st.is_ok()) return st;
    x.normalize();
    if (x.dot(out) < 0) x = -x;
    const double change = (x - out).norm();
    out = x;
    if (change < kInverseTolerance) break;
  }
  return {};
}

// out := J^-1 rhs, with rhs first made orthogonal to psi (J's range) and the result to phi.
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

// J and B at u, B = I for a problem without a time-dependent form
Status jacobian_and_mass(Problem& problem, const Vector& u, SparseMatrix& J, SparseMatrix& B) {
  if (Status st = jacobian(problem, u, J); !st.is_ok()) return st;
  if (!has_time_form(problem)) {
    B.resize(u.size(), u.size());
    B.setIdentity();
    return {};
  }
  B = problem.jacobian_pattern();
  return problem.mass_matrix(u, B);
}

// A normal form of `kind` begun: out emptied and named, J and B at u
Status begin(Problem& problem, const Vector& u, NormalForm::Kind kind, const char* type, NormalForm& out,
             SparseMatrix& J, SparseMatrix& B) {
  out = {};
  out.kind = kind;
  out.type = type;
  return jacobian_and_mass(problem, u, J, B);
}

// <psi, B phi>, with B = I for a problem without a time-dependent form
Status weighted(Problem& problem, const Vector& u, const Vector& psi, const Vector& phi, double& out) {
  if (!has_time_form(problem)) {
    out = psi.dot(phi);
    return {};
  }
  Vector Bphi;
  Status st = problem.time_residual(u, phi, Bphi);
  out = psi.dot(Bphi);
  return st;
}

// J + i s B, factorised as the real matrix [J, -s B; s B, J] (interleaved) by the real sparse LU (MUMPS where the
// options pick it: on a coupled problem of 50,000 unknowns 2.8 times faster than UMFPACK's complex LU);
// its transpose is the block form of (J + i s B)^H.
class ShiftedLU {
 public:
  // one symbolic analysis, by METIS (the `best` ordering's search would cost more than the
  // factorisations it speeds up), kept for a second shift
  explicit ShiftedLU(SparseLUOptions options) : lu_(with_metis(options)) {}
  static SparseLUOptions with_metis(SparseLUOptions o) {
    o.ordering = SparseLUOptions::Ordering::Metis;
    return o;
  }
  Status factorize(const SparseMatrix& J, const SparseMatrix& B, double s) {
    // unknowns interleaved (Re x_i, Im x_i): the matrix is J's pattern with 2 x 2 blocks, which the
    // ordering treats as J's (the two halves one after the other fill in several times more)
    n_ = static_cast<int>(J.rows());
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(static_cast<size_t>(2 * J.nonZeros() + 2 * B.nonZeros()));
    for (int k = 0; k < J.outerSize(); ++k)
      for (SparseMatrix::InnerIterator it(J, k); it; ++it) {
        t.emplace_back(2 * it.row(), 2 * it.col(), it.value());
        t.emplace_back(2 * it.row() + 1, 2 * it.col() + 1, it.value());
      }
    for (int k = 0; k < B.outerSize(); ++k)
      for (SparseMatrix::InnerIterator it(B, k); it; ++it) {
        t.emplace_back(2 * it.row(), 2 * it.col() + 1, -s * it.value());
        t.emplace_back(2 * it.row() + 1, 2 * it.col(), s * it.value());
      }
    SparseMatrix M(2 * n_, 2 * n_);
    M.setFromTriplets(t.begin(), t.end());
    M.makeCompressed();
    return lu_.factorize(M);
  }
  // (J + i s B) x = b, or (J + i s B)^H x = b; refinement_steps as SparseLU::solve's (0: a plain
  // solve, about a fifth of a refined one, where an iteration corrects its errors anyway)
  Status solve(const ComplexVector& b, ComplexVector& x, bool adjoint = false, int refinement_steps = -1) {
    Vector rhs(2 * n_), y;
    for (int i = 0; i < n_; ++i) {
      rhs[2 * i] = b[i].real();
      rhs[2 * i + 1] = b[i].imag();
    }
    Status st = lu_.solve(rhs, y, adjoint, refinement_steps);
    if (!st.is_ok()) return st;
    x.resize(n_);
    for (int i = 0; i < n_; ++i) x[i] = Complex(y[2 * i], y[2 * i + 1]);
    return {};
  }

 private:
  SparseLU lu_;
  int n_ = 0;
};

// GMRES for A x = b with a fixed, linear right preconditioner P (x = P y), complex, from x = 0: modified
// Gram-Schmidt applied twice (the Krylov basis stays orthogonal to rounding where the space nearly
// closes), the small least-squares problem solved by QR at each step. Returns the iterations
// taken once the residual estimate is below tol |b|, or -1 after max_iterations.
template <class Apply, class Precondition>
int gmres(const Apply& A, const Precondition& P, const ComplexVector& b, ComplexVector& x, double tol,
          int max_iterations) {
  const double beta = b.norm();
  x = ComplexVector::Zero(b.size());
  if (beta == 0.0) return 0;
  std::vector<ComplexVector> V{b / beta};
  Eigen::MatrixXcd H = Eigen::MatrixXcd::Zero(max_iterations + 1, max_iterations);
  for (int k = 0; k < max_iterations; ++k) {
    ComplexVector w = A(P(V[static_cast<size_t>(k)]));
    for (int pass = 0; pass < 2; ++pass)
      for (int i = 0; i <= k; ++i) {
        const Complex c = V[static_cast<size_t>(i)].dot(w);
        H(i, k) += c;
        w -= c * V[static_cast<size_t>(i)];
      }
    H(k + 1, k) = w.norm();
    ComplexVector e = ComplexVector::Zero(k + 2);
    e[0] = beta;
    const Eigen::MatrixXcd Hk = H.topLeftCorner(k + 2, k + 1);
    const ComplexVector y = Hk.householderQr().solve(e);
    if ((e - Hk * y).norm() <= tol * beta || H(k + 1, k).real() == 0.0) {
      ComplexVector v = ComplexVector::Zero(b.size());  // x = P (V y): P is linear, V alone is kept
      for (int i = 0; i <= k; ++i) v += y[i] * V[static_cast<size_t>(i)];
      x = P(v);
      return k + 1;
    }
    V.push_back(w / H(k + 1, k).real());
  }
  return -1;
}

// (J + i s B) x = b for s != omega by GMRES, preconditioned by the factorisation of J + i omega B
// at the Hopf point, deflated of its critical mode: with B q its image and p^H B q = 1,
//   P v = (I - q p^H B) lu1^-1 (v - B q p^H v) + q p^H v / (i (s - omega)),
// exact on q ((J + i s B) q = i (s - omega) B q) and, on another mode of J phi = sigma B phi,
// (J + i s B) P = (sigma + i s) / (sigma + i omega): near 1 but for the modes within a few omega
// of the pair, GMRES's outliers. h20 (s = 2 omega) costs solves on lu1 instead of a factorisation
// of its own: at the Hopf point of docs/normal_forms.md's cost table 28 iterations, 0.44 s against
// 0.76 s. (Solves with J, s = 0, took 32 iterations each there, 0.5 s, more than J's real
// factorisation, 0.21 s, and its two solves: they are not done this way.) GMRES's residual
// estimate below 1e-12 |b|, the residual of the result checked below 1e-10 |b|; a solve that does
// not get there in max_iterations (NormalForms' krylov_iterations) reports -1 and its caller
// factorises instead.
class DeflatedShiftSolver {
 public:
  DeflatedShiftSolver(const SparseMatrix& J, const SparseMatrix& B, ShiftedLU& lu1, const ComplexVector& q,
                      const ComplexVector& p, double omega, int max_iterations)
      : J_(J), B_(B), lu1_(lu1), q_(q), p_(p), omega_(omega), max_iterations_(max_iterations) {
    Bq_ = times(B, q);
    const SparseMatrix Bt = B.transpose();
    Btp_ = times(Bt, p);  // p^H B x = (B^T p)^H x, B real
  }
  static ComplexVector times(const SparseMatrix& M, const ComplexVector& v) {
    return ComplexVector(M * v.real().eval() + Complex(0.0, 1.0) * (M * v.imag().eval()).cast<Complex>());
  }
  // iterations, -1 where not solved
  int solve(double s, const ComplexVector& b, ComplexVector& x) const {
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

 private:
  static constexpr double kTolerance = 1e-12;  // of GMRES's residual estimate
  static constexpr double kCheck = 1e-10;      // of the residual computed from the result
  const SparseMatrix& J_;
  const SparseMatrix& B_;
  ShiftedLU& lu1_;
  ComplexVector q_, p_, Bq_, Btp_;
  double omega_;
  int max_iterations_;
};

// The critical pair at a Hopf point on lu1, the factorisation of J + i omega B: q with (J + i
// omega B) q = 0 by inverse iteration from the guess (whichever of the pair it is: the one J + i
// omega B nearly annuls) or a generic start, p with (J + i omega B)^H p = 0, both of unit norm;
// omega refined by the Rayleigh quotient sigma = p^H J q / p^H B q = -i omega.
Status critical_pair(const SparseMatrix& J, const SparseMatrix& B, ShiftedLU& lu1, const Eigen::VectorXcd* guess,
                     double& omega, ComplexVector& q, ComplexVector& p) {
  const auto times = &DeflatedShiftSolver::times;
  const Complex I(0.0, 1.0);
  const int n = static_cast<int>(J.rows());
  q = generic_start(n).cast<Complex>();
  if (guess && guess->size() == n && guess->norm() > 0) {
    const ComplexVector g = guess->normalized(), gc = g.conjugate();
    const double rg = (times(J, g) + I * omega * times(B, g)).norm(),
                 rc = (times(J, gc) + I * omega * times(B, gc)).norm();
    q = rg <= rc ? g : gc;
  }
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

// J at u factorised, and J's null vector from the guess (or a generic start)
Status factorised_null_vector(Problem& problem, const Vector& u, const Vector* guess, SparseLU& lu, NormalForm& out) {
  SparseMatrix J;
  Status st = jacobian(problem, u, J);
  if (!st.is_ok()) return st;
  if (st = factorise(lu, J, out.factorisations); !st.is_ok()) return st;
  const bool usable = guess && guess->size() == u.size() && guess->norm() > 0;
  return null_vector(lu, usable ? *guess : generic_start(static_cast<int>(u.size())), false, out.phi);
}

void record(const HigherDerivatives& d, NormalForm& out) {
  out.exact_derivatives = d.method() == HigherDerivatives::Method::Exact;
  out.derivatives = d.method_name();
  out.derivative_evaluations = d.evaluations();
  out.derivative_seconds = d.seconds();
}

// D o[q] of every observable by central differences along Re q and Im q (a step of 1e-6 of the
// state's size: observables are evaluated in double, their rounding is eps / 1e-6 relative), and
// the orbit's amplitude of each, 2 |z| |D o[q]| per sqrt(|lambda - lambda0|)
Status observable_amplitudes(Problem& problem, const Vector& u, const ComplexVector& q, NormalForm& out) {
  const size_t m = problem.observable_names().size();
  out.observable_amplitudes.assign(m, NAN);
  if (m == 0 || out.amplitude_coefficient == 0.0) return {};
  const double h = 1e-6 * std::max(1.0, u.lpNorm<Eigen::Infinity>());
  std::vector<double> plus, minus;
  std::vector<Complex> derivative(m, 0.0);
  for (int part = 0; part < 2; ++part) {
    const Vector d = part == 0 ? Vector(q.real()) : Vector(q.imag());
    Status st = problem.observables(u + h * d, plus);
    if (st.is_ok()) st = problem.observables(u - h * d, minus);
    if (!st.is_ok()) return st;
    for (size_t i = 0; i < m; ++i)
      derivative[i] += (part == 0 ? Complex(1.0) : Complex(0.0, 1.0)) * ((plus[i] - minus[i]) / (2.0 * h));
  }
  // amplitude_coefficient = 2 sqrt(|g' / Re c1|) = 2 |z| / sqrt(|d|) for |q|_inf = 1
  for (size_t i = 0; i < m; ++i) out.observable_amplitudes[i] = out.amplitude_coefficient * std::abs(derivative[i]);
  return {};
}

}  // namespace

std::string NormalForm::summary() const {
  switch (kind) {
    case Kind::Fold:
      return fmt::format("fold: curvature {:.6g} (a {:.6g}, b {:.6g}), a {} of the parameter", curvature, a, b,
                         curvature < 0 ? "maximum" : "minimum");
    case Kind::FoldHopf:
      return fmt::format(
          "fold-Hopf: g200 {:.6g}, g011 {:.6g}, g110 {:.6g}{:+.6g}i, omega {:.6g}; s = {}, theta = {:.6g}", a, b,
          c1.real(), c1.imag(), omega, a * b > 0 ? 1 : (a * b < 0 ? -1 : 0), c);
    case Kind::BogdanovTakens:
      return fmt::format("Bogdanov-Takens: a {:.6g}, b {:.6g} (w0' = w1, w1' = beta1 + beta2 w1 + a w0^2 + b w0 w1)", a,
                         b);
    case Kind::Cusp:
      return fmt::format("cusp: c {:.6g}, lambda - lambda0 = {:.6g} eps^3 through it (a {:.3g}, b {:.6g})", c, cubic, a,
                         b);
    case Kind::BranchPoint:
      if (type.rfind("pitchfork", 0) == 0)
        return fmt::format("{}: cubic {:.6g}, branches toward {} parameter (a {:.3g}, b {:.6g}, c {:.6g})", type, cubic,
                           side > 0 ? "larger" : "smaller", a, b, c);
      return fmt::format("{}: a {:.6g}, b {:.6g}, c {:.6g}", type, a, b, c);
    case Kind::Hopf:
      return fmt::format("{}: l1 {:.6g}, omega {:.6g}, period {:.6g}, amplitude {:.4g} sqrt(|d|) for {} parameter",
                         type, l1, omega, period, amplitude_coefficient, side > 0 ? "larger" : "smaller");
  }
  return type;
}

namespace {

// A fold's phi, psi, a and b (NormalForms::fold), J factorised in lu.
Status fold_parts(Problem& problem, int parameter, const Vector& u, const Vector* guess, HigherDerivatives& d,
                  SparseLU& lu, NormalForm& out) {
  Status st = factorised_null_vector(problem, u, guess, lu, out);
  if (!st.is_ok()) return st;
  Vector Fl;
  if (st = problem.parameter_derivative(parameter, u, Fl); !st.is_ok()) return st;
  if (guess && guess->size() == u.size() && out.phi.dot(*guess) < 0) out.phi = -out.phi;
  const Vector left_start = Fl.norm() > 0 ? Vector(Fl) : generic_start(u.size());
  if (st = null_vector(lu, left_start, true, out.psi); !st.is_ok()) return st;
  out.b = out.psi.dot(Fl);
  if (out.b < 0) {
    out.psi = -out.psi;
    out.b = -out.b;
  }
  Vector D2;
  if (st = d.second({out.phi}, {out.phi}, D2); !st.is_ok()) return st;
  out.a = out.psi.dot(D2);
  out.curvature = -out.a / out.b;
  return {};
}

}  // namespace

Status NormalForms::fold(Problem& problem, int parameter, const Vector& u, const Vector* guess, NormalForm& out) {
  const auto t0 = std::chrono::steady_clock::now();
  out = {};
  out.kind = NormalForm::Kind::Fold;
  out.type = "fold";
  HigherDerivatives d(problem, parameter, u, force_differences_);
  SparseLU lu(lu_);
  if (Status st = fold_parts(problem, parameter, u, guess, d, lu, out); !st.is_ok()) return st;
  record(d, out);
  out.seconds = seconds_since(t0);
  return {};
}

Status NormalForms::cusp(Problem& problem, int parameter, const Vector& u, const Vector* guess, NormalForm& out) {
  const auto t0 = std::chrono::steady_clock::now();
  out = {};
  out.kind = NormalForm::Kind::Cusp;
  out.type = "cusp";
  HigherDerivatives d(problem, parameter, u, force_differences_);
  SparseLU lu(lu_);
  Status st = fold_parts(problem, parameter, u, guess, d, lu, out);
  if (!st.is_ok()) return st;
  if (!guess) {  // c is odd in phi: phi's entry of largest magnitude positive
    Eigen::Index k = 0;
    out.phi.cwiseAbs().maxCoeff(&k);
    if (out.phi[k] < 0) out.phi = -out.phi;
  }
  // u = u0 + eps phi + eps^2 h2 / 2 + ..., J h2 = -F_uu[phi, phi] (solvable where a = 0; h2
  // orthogonal to phi); the eps^3 term of the reduced equation is c / 6
  const Direction P{out.phi};
  Vector D2, h2, D3;
  if (st = d.second(P, P, D2); !st.is_ok()) return st;
  if (st = solve_bordered(lu, out.phi, out.psi, -D2, h2); !st.is_ok()) return st;
  if (st = d.second(P, {h2}, D2); !st.is_ok()) return st;
  if (st = d.third(P, P, P, D3); !st.is_ok()) return st;
  out.c = out.psi.dot(D3) + 3.0 * out.psi.dot(D2);
  out.cubic = -out.c / (6.0 * out.b);
  record(d, out);
  out.seconds = seconds_since(t0);
  return {};
}

Status NormalForms::bogdanov_takens(Problem& problem, int parameter, const Vector& u, NormalForm& out) {
  const auto t0 = std::chrono::steady_clock::now();
  SparseMatrix J, B;
  Status st = begin(problem, u, NormalForm::Kind::BogdanovTakens, "Bogdanov-Takens", out, J, B);
  if (!st.is_ok()) return st;
  const int n = static_cast<int>(u.size());
  HigherDerivatives d(problem, parameter, u, force_differences_);
  SparseLU lu(lu_);
  if (st = factorise(lu, J, out.factorisations); !st.is_ok()) return st;
  // the Jordan chain of A = -B^-1 J at the double zero: J q0 = 0, -J q1 = B q0; and on the left,
  // with p = B^T psi (p^T f for f = -B^-1 F is -psi^T F): J^T psi1 = 0, -J^T psi0 = B^T psi1
  Vector q0, q1, psi0, psi1;
  if (st = smallest_singular_vector(lu, generic_start(n), false, q0); !st.is_ok()) return st;
  Eigen::Index k = 0;
  q0.cwiseAbs().maxCoeff(&k);
  if (q0[k] < 0) q0 = -q0;  // a and b are odd in q0
  if (st = smallest_singular_vector(lu, generic_start(n), true, psi1); !st.is_ok()) return st;
  // psi1 is orthogonal to q0 (the zero is defective), so J's range and null space are no
  // complements and a projected solve with J fails; the bordered matrix [J psi1; q0^T 0] is
  // regular there (psi1 outside J's range, q0 outside J^T's): q1 from it (q1 orthogonal to q0),
  // psi0 from its transpose (psi0 orthogonal to psi1)
  SparseMatrix M(n + 1, n + 1);
  {
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(static_cast<size_t>(J.nonZeros() + 2 * n));
    for (int col = 0; col < J.outerSize(); ++col)
      for (SparseMatrix::InnerIterator it(J, col); it; ++it) t.emplace_back(it.row(), it.col(), it.value());
    for (int i = 0; i < n; ++i) {
      t.emplace_back(i, n, psi1[i]);
      t.emplace_back(n, i, q0[i]);
    }
    M.setFromTriplets(t.begin(), t.end());
    M.makeCompressed();
  }
  SparseLU bordered(lu_);
  if (st = factorise(bordered, M, out.factorisations); !st.is_ok()) return st;
  Vector rhs = Vector::Zero(n + 1), x;
  rhs.head(n) = -(B * q0);
  if (st = bordered.solve(rhs, x); !st.is_ok()) return st;
  q1 = x.head(n);
  // the border's multiplier is psi1^T B q0 (up to |psi1| = 1): zero at a Bogdanov-Takens point,
  // of the order of omega at one located on a Hopf curve; a large one means the zero is simple
  const double size = (B * q0).norm();
  if (!(std::abs(x[n]) <= kNotBogdanovTakens * size))
    return {StatusCode::InvalidState,
            fmt::format("not a Bogdanov-Takens point: the zero eigenvalue is simple (psi1^T B q0 = {:.3g} of |B q0|)",
                        std::abs(x[n]) / size)};
  rhs.head(n) = -(B.transpose() * psi1);
  if (st = bordered.solve(rhs, x, true); !st.is_ok()) return st;
  psi0 = x.head(n);
  // <p1, q1> = psi1^T B q1 = 1 (then <p0, q0> = 1 too), <p0, q1> = 0 by q1 += alpha q0
  const double scale = psi1.dot(B * q1);
  if (!(std::abs(scale) > 1e-12 * (B * q1).norm()))
    return {StatusCode::InvalidState, "no Jordan chain at the Bogdanov-Takens point (psi1^T B q1 = 0)"};
  psi1 /= scale;
  psi0 /= scale;
  q1 -= psi0.dot(B * q1) / psi0.dot(B * q0) * q0;
  // f_uu[x, y] = -B^-1 D^2 R[(x, A x), (y, A y)] with R = B(u) udot + F(u): A q0 = 0, A q1 = q0
  const Direction Q0{q0}, Q1{q1, 0.0, q0};
  Vector D00, D01;
  if (st = d.second(Q0, Q0, D00); !st.is_ok()) return st;
  if (st = d.second(Q0, Q1, D01); !st.is_ok()) return st;
  out.a = -0.5 * psi1.dot(D00);
  out.b = -psi0.dot(D00) - psi1.dot(D01);
  out.phi = q0;
  out.psi = psi1;
  record(d, out);
  out.seconds = seconds_since(t0);
  return {};
}

Status NormalForms::fold_hopf(Problem& problem, int parameter, const Vector& u, double omega, NormalForm& out) {
  const auto t0 = std::chrono::steady_clock::now();
  SparseMatrix J, B;
  Status st = begin(problem, u, NormalForm::Kind::FoldHopf, "fold-Hopf", out, J, B);
  if (!st.is_ok()) return st;
  const int n = static_cast<int>(u.size());
  HigherDerivatives d(problem, parameter, u, force_differences_);
  // the zero eigenvalue: J q0 = 0, J^T psi0 = 0, psi0^T B q0 = 1 (<p0, q0> = 1 for p0 = B^T psi0)
  SparseLU lu(lu_);
  Vector q0, psi0;
  if (st = factorise(lu, J, out.factorisations); !st.is_ok()) return st;
  if (st = null_vector(lu, generic_start(n), false, q0); !st.is_ok()) return st;
  Eigen::Index k = 0;
  q0.cwiseAbs().maxCoeff(&k);
  if (q0[k] < 0) q0 = -q0;  // g200, g011, g110 are odd in q0
  if (st = null_vector(lu, generic_start(n), true, psi0); !st.is_ok()) return st;
  const double psi_b_q = psi0.dot(B * q0);
  if (!(std::abs(psi_b_q) > 1e-12 * psi0.norm() * (B * q0).norm()))
    return {StatusCode::InvalidState, "the zero eigenvalue is not simple (psi0^T B q0 = 0): a Bogdanov-Takens point?"};
  psi0 /= psi_b_q;
  // the pair +-i omega: (J + i omega B) q1 = 0, |q1|_2 = 1 with its largest entry real and positive;
  // (J + i omega B)^H p1 = 0, p1^H B q1 = 1
  ShiftedLU lu1(lu_);
  ++out.factorisations;
  omega = std::abs(omega);
  if (st = lu1.factorize(J, B, omega); !st.is_ok()) return st;
  ComplexVector q1, p1;
  if (st = critical_pair(J, B, lu1, nullptr, omega, q1, p1); !st.is_ok()) return st;
  q1.cwiseAbs().maxCoeff(&k);
  q1 *= std::conj(q1[k]) / std::abs(q1[k]);
  p1 /= std::conj(p1.dot(DeflatedShiftSolver::times(B, q1)));
  // <p, f_uu[x, y]> = -psi^H D^2 R[(x, A x), (y, A y)]: A q0 = 0, A q1 = i omega q1
  const Complex I(0.0, 1.0);
  const ComplexDirection Q0{q0.cast<Complex>(), 0.0, {}}, Q1{q1, 0.0, I * omega * q1},
      Q1bar{q1.conjugate(), 0.0, -I * omega * q1.conjugate()};
  ComplexVector D;
  if (st = d.second(Q0, Q0, D); !st.is_ok()) return st;
  out.a = -psi0.dot(D.real());  // g200
  if (st = d.second(Q1, Q1bar, D); !st.is_ok()) return st;
  out.b = -psi0.dot(D.real());  // g011
  if (st = d.second(Q0, Q1, D); !st.is_ok()) return st;
  out.c1 = -p1.dot(D);                                 // g110
  out.c = out.a != 0.0 ? out.c1.real() / out.a : NAN;  // theta
  out.omega = omega;
  out.period = 2.0 * std::numbers::pi / omega;
  out.phi = q0;
  out.psi = psi0;
  out.q = q1;
  record(d, out);
  out.seconds = seconds_since(t0);
  return {};
}

Status NormalForms::branch_point(Problem& problem, int parameter, const Vector& u, const Vector* guess,
                                 NormalForm& out) {
  const auto t0 = std::chrono::steady_clock::now();
  out = {};
  out.kind = NormalForm::Kind::BranchPoint;
  HigherDerivatives d(problem, parameter, u, force_differences_);
  SparseLU lu(lu_);
  Status st = factorised_null_vector(problem, u, guess, lu, out);
  if (!st.is_ok()) return st;
  if (st = null_vector(lu, generic_start(u.size()), true, out.psi); !st.is_ok()) return st;
  if (out.psi.dot(out.phi) < 0) out.psi = -out.psi;
  Vector Fl, v;
  if (st = problem.parameter_derivative(parameter, u, Fl); !st.is_ok()) return st;
  if (st = solve_bordered(lu, out.phi, out.psi, -Fl, v); !st.is_ok()) return st;
  // the direction of the continued branch's family, (v, 1) scaled to unit length
  const double scale = std::sqrt(v.squaredNorm() + 1.0);
  const Direction P{out.phi}, E{v / scale, 1.0 / scale};
  Vector D2;
  if (st = d.second(P, P, D2); !st.is_ok()) return st;
  out.a = out.psi.dot(D2);
  if (st = d.second(P, E, D2); !st.is_ok()) return st;
  out.b = out.psi.dot(D2);
  if (st = d.second(E, E, D2); !st.is_ok()) return st;
  out.c = out.psi.dot(D2);
  double psi_b_phi = 0.0;
  if (st = weighted(problem, u, out.psi, out.phi, psi_b_phi); !st.is_ok()) return st;
  // d(growth rate of the critical mode) / d lambda along (v, 1): -<psi, D2[phi, (v, 1)]> / <psi, B phi>
  out.growth_rate_derivative = psi_b_phi != 0.0 ? -out.b * scale / psi_b_phi : 0.0;
  const double disc = out.b * out.b - out.a * out.c;
  auto tangent = [&](int k, double al, double be) {
    const double n = std::hypot(al, be);
    out.tangent_u[k] = (al * out.phi + be * E.u) / n;
    out.tangent_lambda[k] = be * E.lambda / n;
  };
  const double size = std::max(std::abs(out.b), std::abs(out.c));
  if (std::abs(out.a) <= kZeroCoefficient * size && out.b != 0.0) {
    // be = 0 is a root: a branch along phi that turns at the point; its lambda from the cubic terms
    Vector w2, D3;
    if (st = d.second(P, P, D2); !st.is_ok()) return st;
    if (st = solve_bordered(lu, out.phi, out.psi, -0.5 * D2, w2); !st.is_ok()) return st;
    if (st = d.second(P, {w2}, D2); !st.is_ok()) return st;
    if (st = d.third(P, P, P, D3); !st.is_ok()) return st;
    out.cubic = -(out.psi.dot(D2) + out.psi.dot(D3) / 6.0) / (out.b * scale);
    out.second_u = 2.0 * (w2 + out.cubic * v);
    out.second_lambda = 2.0 * out.cubic;
    out.side = out.cubic > 0 ? 1 : -1;
    const bool super = out.growth_rate_derivative != 0.0 && (out.growth_rate_derivative > 0) == (out.cubic > 0);
    out.type = super ? "pitchfork (supercritical)" : "pitchfork (subcritical)";
    tangent(0, 1.0, 0.0);
    tangent(1, -out.c / (2.0 * out.b), 1.0);
  } else if (disc >= 0.0) {
    out.type = "transcritical";
    const double r = std::sqrt(disc);
    // roots al / be of a al^2 + 2 b al be + c be^2 = 0, written to avoid cancellation
    const double q = -(out.b + std::copysign(r, out.b));
    if (q == 0.0) {
      tangent(0, 1.0, 0.0);
      tangent(1, 0.0, 1.0);
    } else {
      tangent(0, q, out.a);  // al / be = q / a
      tangent(1, out.c, q);  // al / be = c / q
    }
  } else {
    out.type = "isolated point";  // no real branch through it besides the point itself
  }
  record(d, out);
  out.seconds = seconds_since(t0);
  return {};
}

Status NormalForms::hopf(Problem& problem, int parameter, const Vector& u, double omega, const Eigen::VectorXcd* guess,
                         NormalForm& out) {
  const auto t0 = std::chrono::steady_clock::now();
  out = {};
  out.kind = NormalForm::Kind::Hopf;
  HigherDerivatives d(problem, parameter, u, force_differences_);
  SparseMatrix J, B;
  Status st = jacobian_and_mass(problem, u, J, B);
  if (!st.is_ok()) return st;
  omega = std::abs(omega);
  const Complex I(0.0, 1.0);
  // the factorisations' time
  auto timed = [&out](auto&& factorise_it) {
    const auto t = std::chrono::steady_clock::now();
    Status s = factorise_it();
    out.factor_seconds += seconds_since(t);
    return s;
  };
  // the factorisation q and p need, on which GMRES finds h20 (DeflatedShiftSolver)
  ShiftedLU lu1(lu_);
  ++out.factorisations;
  if (st = timed([&] { return lu1.factorize(J, B, omega); }); !st.is_ok()) return st;
  const auto times = &DeflatedShiftSolver::times;
  ComplexVector q, p;
  if (st = critical_pair(J, B, lu1, guess, omega, q, p); !st.is_ok()) return st;
  Eigen::Index k = 0;
  q.cwiseAbs().maxCoeff(&k);
  q *= std::conj(q[k]) / std::norm(q[k]);  // q_k = 1
  p /= std::conj(p.dot(times(B, q)));      // p^H B q = 1
  out.q = q;
  out.omega = omega;
  out.period = 2.0 * std::numbers::pi / omega;
  out.amplitude_entry = static_cast<int>(k);

  const ComplexDirection Q{q, 0.0, I * omega * q}, Qbar{q.conjugate(), 0.0, -I * omega * q.conjugate()};
  // solves with J on a factorisation of its own (the deflated GMRES needed 30 iterations on the
  // cost table's point, more than a real factorisation costs); with J + 2 i omega B by GMRES on lu1, or where
  // that fails on a factorisation of its own
  const DeflatedShiftSolver shifted(J, B, lu1, q, p, omega, krylov_iterations_);
  SparseLU lu(lu_);
  if (st = timed([&] { return factorise(lu, J, out.factorisations); }); !st.is_ok()) return st;
  ComplexVector r;
  // h11: J h11 = -D2R[Q, Qbar] (real)
  if (st = d.second(Q, Qbar, r); !st.is_ok()) return st;
  Vector h11;
  if (st = lu.solve(-Vector(r.real()), h11); !st.is_ok()) return st;
  // h20: (J + 2 i omega B) h20 = -D2R[Q, Q]
  if (st = d.second(Q, Q, r); !st.is_ok()) return st;
  ComplexVector h20;
  if (const int it = shifted.solve(2.0 * omega, -r, h20); it >= 0) {
    out.gmres_iterations += it;
  } else {
    // lu1's last use: refactorised on its own analysis (one complex factorisation in memory)
    ++out.factorisations;
    if (st = timed([&] { return lu1.factorize(J, B, 2.0 * omega); }); !st.is_ok()) return st;
    if (st = lu1.solve(-r, h20); !st.is_ok()) return st;
  }
  const ComplexDirection H20{h20, 0.0, 2.0 * I * omega * h20}, H11{h11.cast<Complex>(), 0.0, {}};
  ComplexVector sum, t;
  if (st = d.third(Q, Q, Qbar, sum); !st.is_ok()) return st;
  if (st = d.second(Qbar, H20, t); !st.is_ok()) return st;
  sum += t;
  if (st = d.second(Q, H11, t); !st.is_ok()) return st;
  sum += 2.0 * t;
  out.c1 = -0.5 * p.dot(sum);
  out.l1 = out.c1.real() / omega;
  // transversality: d(growth rate)/d lambda = -p^H D2R[Q, (v, 1)], J v = -F_lambda
  Vector Fl, v;
  if (st = problem.parameter_derivative(parameter, u, Fl); !st.is_ok()) return st;
  if (st = lu.solve(-Fl, v); !st.is_ok()) return st;
  if (st = d.second(Q, ComplexDirection{v.cast<Complex>(), 1.0, {}}, r); !st.is_ok()) return st;
  out.growth_rate_derivative = -p.dot(r).real();
  const double g = out.growth_rate_derivative, rc = out.c1.real();
  if (g != 0.0 && rc != 0.0) {
    out.side = -g / rc > 0 ? 1 : -1;
    out.amplitude_coefficient = 2.0 * std::sqrt(std::abs(g / rc));
  }
  if (st = observable_amplitudes(problem, u, q, out); !st.is_ok()) return st;
  out.type = out.l1 < 0 ? "Hopf (supercritical)" : "Hopf (subcritical)";
  record(d, out);
  out.seconds = seconds_since(t0);
  return {};
}

}  // namespace keller
