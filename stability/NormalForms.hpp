// Normal forms of located points of F(u, lambda) = 0, B du/dt = -F: what happens beyond a fold, a
// simple branch point or a Hopf point, from second and third derivatives of F (and of B u', where
// B depends on u) at the point (core/HigherDerivatives.hpp: exact where the problem offers them).
//
// Conventions (docs/normal_forms.md):
// - phi is J's null vector with |phi|_2 = 1 (Hopf: q, with max_i |q_i| = 1 and that entry real
//   and positive), psi J's left null vector with |psi|_2 = 1 (Hopf: p with p^H B q = 1).
// - Fold: along u = u0 + eps phi + O(eps^2), lambda = lambda0 + curvature eps^2 / 2, curvature =
//   -a / b with a = <psi, F_uu[phi, phi]> and b = <psi, F_lambda> (psi's sign makes b > 0): a fold
//   with curvature < 0 is a maximum of lambda along the branch, > 0 a minimum.
// - Cusp (a fold whose a vanishes, located on a fold curve): the reduced equation b (lambda -
//   lambda0) + a eps^2 / 2 + c eps^3 / 6 = 0 with c = <psi, F_uuu[phi, phi, phi] + 3 F_uu[phi, h2]>,
//   J h2 = -F_uu[phi, phi] (h2 orthogonal to phi): the branch through the cusp at fixed second
//   parameter has lambda = lambda0 + cubic eps^3, cubic = -c / (6 b), an inflection in lambda.
// - Bogdanov-Takens (a double zero eigenvalue of A = -B^-1 J with a Jordan block, where a Hopf
//   curve's omega vanishes): Kuznetsov's w0' = w1, w1' = beta1 + beta2 w1 + a w0^2 + b w0 w1 with
//   A q0 = 0, A q1 = q0, p1^T A = 0, p0^T A = p1^T, <p0, q0> = <p1, q1> = 1, <p0, q1> = <p1, q0> =
//   0, |q0|_2 = 1 with its largest entry positive (a, b scale with q0): a = <p1, f_uu[q0, q0]> / 2,
//   b = <p0, f_uu[q0, q0]> + <p1, f_uu[q0, q1]>, for f = -B(u)^-1 F(u) (the B' terms through D^2 R
//   with rates A q).
// - Fold-Hopf (a simple zero and a pair +-i omega of A): Kuznetsov's w0' = beta1 + g200 w0^2 / 2 +
//   g011 |w1|^2 + ..., w1' = (beta2 + i omega) w1 + g110 w0 w1 + ..., with A q0 = 0, A q1 = i omega
//   q1, p0^T A = 0, p1^H A = i omega p1^H, <p0, q0> = <p1, q1> = 1, |q0|_2 = |q1|_2 = 1 (q0's
//   largest entry positive, q1's real and positive): g200 = <p0, f_uu[q0, q0]>, g011 = <p0,
//   f_uu[q1, conj q1]>, g110 = <p1, f_uu[q0, q1]>. The unfolding's type is s = sign(g200 g011)
//   and theta = Re g110 / g200 (Kuznetsov, Lemma 8.10); the third-order E is not computed.
// - Simple branch point: the algebraic bifurcation equation a al^2 + 2 b al be + c be^2 = 0 in the
//   tangents al phi + be (v, 1) (J v = -F_lambda, v orthogonal to phi, (v, 1) scaled to unit
//   length), a, b, c = <psi, D^2 F> on (phi, 0) and (v, 1); two real roots (b^2 > a c):
//   transcritical, or a pitchfork where one root is be = 0 (a = 0, up to 1e-6 of |b| and |c|),
//   whose branch u = u0 + eps phi has lambda = lambda0 + cubic eps^2. Supercritical: the
//   bifurcating branches lie on the side where the continued branch is unstable (growth rate
//   -<psi, J_lambda phi> / <psi, B phi>; B = I for a problem without a time-dependent form).
// - Hopf: the critical eigenvalue sigma = -i omega of J phi = sigma B phi (growth rate -sigma),
//   the normal form z' = (g' (lambda - lambda0) + i omega) z + c1 z |z|^2 of the amplitude z of
//   u = u0 + z q + conj(z q) + ..., first Lyapunov coefficient l1 = Re c1 / omega (< 0:
//   supercritical, stable orbits; > 0: subcritical), period 2 pi / omega, and the orbit's
//   amplitude max_t |u_i - u0_i| = 2 |z| |q_i| with |z|^2 = -g' (lambda - lambda0) / Re c1: at the
//   entry where |q_i| = 1, amplitude_coefficient sqrt(|lambda - lambda0|) on the side `side`, and
//   for each observable o, 2 |z| |D o[q]|.
#pragma once

#include <complex>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/Problem.hpp"
#include "core/SparseLU.hpp"
#include "core/Status.hpp"
#include "core/Types.hpp"

namespace keller {

struct NormalForm {
  enum class Kind { Fold, BranchPoint, Hopf, Cusp, BogdanovTakens, FoldHopf };
  Kind kind = Kind::Fold;
  std::string type;  // "fold", "transcritical", "pitchfork (supercritical)", "Hopf (subcritical)", ...
  // fold: a, b; branch point: the bifurcation equation's; cusp: all three; Bogdanov-Takens: a, b;
  // fold-Hopf: a = g200, b = g011, c = theta = Re g110 / g200 (g110 in c1, the pair's in omega)
  double a = 0, b = 0, c = 0;
  double curvature = 0;  // fold, cusp
  double cubic = 0;      // pitchfork: lambda - lambda0 = cubic eps^2 on the branch along phi; cusp: cubic eps^3
  // branch point: the two branches' unit tangents (state, parameter): the pitchfork's bifurcating
  // branch first
  Vector tangent_u[2];
  double tangent_lambda[2] = {0, 0};
  // pitchfork: the bifurcating branch's second derivative in eps, d^2 (u, lambda) / d eps^2 =
  // (2 (w2 + cubic v), 2 cubic) (J w2 = -F_uu[phi, phi] / 2): the parabola a switch predicts along
  Vector second_u;
  double second_lambda = 0;
  double growth_rate_derivative = 0;  // d Re(growth rate) / d lambda along the continued branch
  // Hopf
  double omega = 0, period = 0, l1 = 0;
  std::complex<double> c1 = 0;
  double amplitude_coefficient = 0;
  int amplitude_entry = -1;  // the unknown where |q| = 1
  int side = 0;              // orbits (pitchfork: branches) exist for lambda > lambda0 (+1) or < (-1)
  Eigen::VectorXcd q;        // Hopf: the critical eigenvector as normalised above
  // Hopf: the amplitude of each of the problem's observables on the orbit, max_t |o - o0| =
  // observable_amplitudes[i] sqrt(|lambda - lambda0|) (2 |z| |D o[q]|, D o by central differences)
  std::vector<double> observable_amplitudes;
  Vector phi, psi;  // fold, branch point, cusp; Bogdanov-Takens: q0 and psi1
  bool exact_derivatives = false;
  std::string derivatives;  // how the derivatives were taken
  long factorisations = 0, derivative_evaluations = 0;
  long gmres_iterations = 0;  // Hopf: of the solves by GMRES (NormalFormSolvers.hpp)
  // all; (Hopf) in factorisations; in the derivatives (HigherDerivatives::seconds)
  double seconds = 0, factor_seconds = 0, derivative_seconds = 0;
  // One line for people: the type and the numbers that say what happens beyond the point.
  std::string summary() const;
};

class NormalForms {
 public:
  // force_differences: central differences even where the problem offers exact derivatives.
  // krylov_iterations: at a Hopf point, the solves with J + i s B (q, p, h20) by GMRES on J's real
  // factorisation, or where that takes more, q and p on the factorisation of J + i omega B and h20
  // by GMRES on it: at most this many iterations per solve before it gets a factorisation of its
  // own (NormalFormSolvers.hpp); 0: every solve on a factorisation of its own.
  explicit NormalForms(SparseLUOptions lu = {}, bool force_differences = false, int krylov_iterations = 60)
      : lu_(lu), force_differences_(force_differences), krylov_iterations_(krylov_iterations) {}

  // At a located point u, the parameters at the point's values; `parameter` is lambda's index.
  // guess: a vector close to phi (a fold's tangent, J's null vector at a branch point; null:
  // none). Numerical failures come back as a Status.
  Status fold(Problem& problem, int parameter, const Vector& u, const Vector* guess, NormalForm& out);
  Status branch_point(Problem& problem, int parameter, const Vector& u, const Vector* guess, NormalForm& out);
  // A cusp: a fold whose a vanishes (located on a fold curve); the fold's numbers and the cubic
  // coefficient c (odd in phi: phi's sign from the guess as fold's, or with no guess its entry of
  // largest magnitude positive).
  Status cusp(Problem& problem, int parameter, const Vector& u, const Vector* guess, NormalForm& out);
  // A Bogdanov-Takens point: J has a double zero eigenvalue with one eigenvector (located on a Hopf
  // curve where omega vanishes); a and b of the normal form. A simple zero fails (InvalidState).
  Status bogdanov_takens(Problem& problem, int parameter, const Vector& u, NormalForm& out);
  // A fold-Hopf point: J has a simple zero eigenvalue and a pair +-i omega (located on a Hopf
  // curve where det J changes sign); the second-order coefficients g200, g011, g110.
  Status fold_hopf(Problem& problem, int parameter, const Vector& u, double omega, NormalForm& out);
  // omega: |Im sigma| of the critical pair; guess: its eigenvector (either of the pair; null: none).
  Status hopf(Problem& problem, int parameter, const Vector& u, double omega, const Eigen::VectorXcd* guess,
              NormalForm& out);

 private:
  SparseLUOptions lu_;
  bool force_differences_;
  int krylov_iterations_;
};

}  // namespace keller
