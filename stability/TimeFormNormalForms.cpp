#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include <fmt/format.h>

#include "stability/NormalFormSolvers.hpp"
#include "stability/NormalForms.hpp"

// The normal forms that need the time-dependent form B du/dt = -F: Hopf, fold-Hopf and
// Bogdanov-Takens points (the steady points': NormalForms.cpp).
namespace keller {

using namespace normal_forms;

namespace {

// |psi1^T B q0| above this share of |B q0|: the zero is simple, no Bogdanov-Takens point (the
// located points on a Hopf curve have omega below 1e-4, and psi1^T B q0 of its order)
constexpr double kNotBogdanovTakens = 1e-3;

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
  // J's factorisation, for h11 and the transversality, and where GMRES converges on it
  // (RealLUShiftSolver) for q, p and h20 too
  SparseLU lu(lu_);
  if (st = timed([&] { return factorise(lu, J, out.factorisations); }); !st.is_ok()) return st;
  const RealLUShiftSolver on_j(J, B, lu, krylov_iterations_);
  ComplexVector q, p;
  int iterations = -1;
  if (krylov_iterations_ > 0)
    if (st = critical_pair_on_real_lu(on_j, J, B, guess, omega, q, p, iterations); !st.is_ok()) return st;
  // otherwise on the factorisation of J + i omega B, on which GMRES then finds h20
  // (DeflatedShiftSolver)
  std::optional<ShiftedLU> lu1;
  if (iterations >= 0) {
    out.gmres_iterations += iterations;
  } else {
    lu1.emplace(lu_);
    ++out.factorisations;
    if (st = timed([&] { return lu1->factorize(J, B, omega); }); !st.is_ok()) return st;
    if (st = critical_pair(J, B, *lu1, guess, omega, q, p); !st.is_ok()) return st;
  }
  Eigen::Index k = 0;
  q.cwiseAbs().maxCoeff(&k);
  q *= std::conj(q[k]) / std::norm(q[k]);  // q_k = 1
  p /= std::conj(p.dot(times(B, q)));      // p^H B q = 1
  out.q = q;
  out.omega = omega;
  out.period = 2.0 * std::numbers::pi / omega;
  out.amplitude_entry = static_cast<int>(k);

  const ComplexDirection Q{q, 0.0, I * omega * q}, Qbar{q.conjugate(), 0.0, -I * omega * q.conjugate()};
  ComplexVector r;
  // h11: J h11 = -D2R[Q, Qbar] (real)
  if (st = d.second(Q, Qbar, r); !st.is_ok()) return st;
  Vector h11;
  if (st = lu.solve(-Vector(r.real()), h11); !st.is_ok()) return st;
  // h20: (J + 2 i omega B) h20 = -D2R[Q, Q], by GMRES on J's factorisation or on lu1, where that
  // fails on a factorisation of its own
  if (st = d.second(Q, Q, r); !st.is_ok()) return st;
  ComplexVector h20;
  int it = lu1 ? DeflatedShiftSolver(J, B, *lu1, q, p, omega, krylov_iterations_).solve(2.0 * omega, -r, h20)
               : on_j.solve(2.0 * omega, -r, h20);
  if (it >= 0) {
    out.gmres_iterations += it;
  } else {
    // lu1's last use: refactorised on its own analysis (one complex factorisation in memory)
    if (!lu1) lu1.emplace(lu_);
    ++out.factorisations;
    if (st = timed([&] { return lu1->factorize(J, B, 2.0 * omega); }); !st.is_ok()) return st;
    if (st = lu1->solve(-r, h20); !st.is_ok()) return st;
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
  p1 /= std::conj(p1.dot(times(B, q1)));
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

}  // namespace keller
