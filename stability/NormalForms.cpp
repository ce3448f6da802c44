#include "stability/NormalForms.hpp"

#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "stability/NormalFormSolvers.hpp"

// The normal forms of points of the steady problem: folds, cusps and simple branch points (those
// that need the time-dependent form: TimeFormNormalForms.cpp).
namespace keller {

using namespace normal_forms;

namespace {

// a bifurcation-equation coefficient this small against the others is zero (a pitchfork's a)
constexpr double kZeroCoefficient = 1e-6;

// J at u factorised, and J's null vector from the guess (or a generic start)
Status factorised_null_vector(Problem& problem, const Vector& u, const Vector* guess, SparseLU& lu, NormalForm& out) {
  SparseMatrix J;
  Status st = jacobian(problem, u, J);
  if (!st.is_ok()) return st;
  if (st = factorise(lu, J, out.factorisations); !st.is_ok()) return st;
  const bool usable = guess && guess->size() == u.size() && guess->norm() > 0;
  return null_vector(lu, usable ? *guess : generic_start(static_cast<int>(u.size())), false, out.phi);
}

// <psi, B phi>, with B = I for a problem without a time-dependent form
Status weighted(Problem& problem, const Vector& u, const Vector& psi, const Vector& phi, double& out) {
  if (!has_time_form(problem, u)) {
    out = psi.dot(phi);
    return {};
  }
  Vector Bphi;
  Status st = problem.time_residual(u, phi, Bphi);
  out = psi.dot(Bphi);
  return st;
}

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

}  // namespace keller
