// The formulas and policies of variable-step BDF2 for B du/dt = -F(u), as pure functions of the
// step history, each tested alone on synthetic inputs (docs/dynamics.md): the backward-difference
// coefficients, the predictor, the local-error estimate from the predictor's miss, the next step
// from an error norm, and whether the kept factorisation of the step matrix (c0 / h) B + J still
// serves after the step changed.
#pragma once

#include <array>

#include "core/Types.hpp"

namespace keller {

// The 5-stage SDIRK method of order 4 of Hairer and Wanner (Solving ODEs II, Table IV.6.5): L-stable
// and stiffly accurate, with an embedded method of order 3. Stage i solves B(U_i) K_i + F(U_i) = 0
// for U_i = u_n + h sum_(j <= i) a_ij K_j (a_ii = gamma: every stage's matrix is (1 / (h gamma)) B +
// J), u_(n+1) = U_5 (b is the last row of a), and the local error of the embedded method is
// h sum_j (b_j - b_hat_j) K_j, O(h^4). A one-step method: no start procedure, and a periodic orbit
// is a fixed point of the map of its steps alone (continuation/orbits).
struct SdirkTableau {
  static constexpr int kStages = 5;
  double gamma = 0.0;
  std::array<std::array<double, kStages>, kStages> a{};
  std::array<double, kStages> b{}, b_hat{}, c{};
  // The embedded method's local error estimate h sum_j (b_j - b_hat_j) K_j from the stage rates
  // (the adaptive run's, and the shooting map's check of a frozen grid)
  Vector embedded_error(double h, const std::array<const Vector*, kStages>& K) const;
};
const SdirkTableau& sdirk4();

// Variable-step BDF2 is zero-stable for step ratios h_n / h_(n-1) below 1 + sqrt(2) (Grigorieff
// 1983); the controller never grows a step by more than this, which leaves a margin.
inline constexpr double kMaxStepGrowth = 2.0;
// A rejected step is never cut by more than this factor at once (the error estimate of a step far
// outside the asymptotic range is itself unreliable).
inline constexpr double kMinStepFactor = 0.2;
// The controller aims at this fraction of the tolerance, so that the next step is not rejected for
// a small rise of the error (the usual 0.9 of ODE codes).
inline constexpr double kStepSafety = 0.9;
// After a Newton failure the step is cut by this factor (the predictor was too far for Newton).
inline constexpr double kNewtonFailureShrink = 0.25;
// The step matrix (c0 / h) B + J is refactorised where c0 / h changed by more than this fraction
// since its factorisation (the chord's rate then degrades; CVODE uses the same 30%).
inline constexpr double kMaxMatrixCoefficientChange = 0.3;

// u'(t_(n+1)) ~ (c[0] u_(n+1) + c[1] u_n + c[2] u_(n-1)) / h, h = t_(n+1) - t_n.
// order 1 (backward Euler, the first step): c = (1, -1, 0). order 2: with w = h / h_prev,
// c = ((1 + 2w) / (1 + w), -(1 + w), w^2 / (1 + w)): exact for quadratics.
std::array<double, 3> bdf_coefficients(int order, double h, double h_prev);

// The weights of u_n, u_(n-1), u_(n-2) in the polynomial through the last `points` (1, 2 or 3)
// states extrapolated to t_(n+1) = t_n + h (h1 = t_n - t_(n-1), h2 = t_(n-1) - t_(n-2)): the
// predictor, constant, linear or quadratic. Unused weights are 0.
std::array<double, 3> extrapolation_weights(int points, double h, double h1, double h2);

// The local error of a BDF2 step from the miss of the quadratic predictor: e ~ K (u_(n+1) - u_pred)
// with K = r / (H + r), r = h (1 + w) / (1 + 2 w), H = h + h1 + h2 (both errors are proportional to
// u''' to leading order: the corrector's h^2 (h + h1) u''' (1 + w) / (6 (1 + 2 w)), the predictor's
// h (h + h1) H u''' / 6). Constant steps: K = 2/11.
double bdf2_error_factor(double h, double h1, double h2);

// The local error of the start, two backward Euler steps of h/2 from u_0, from their difference to
// one step of h (Richardson): the full step errs by h^2 u'' / 2, the two halves by h^2 u'' / 4, so
// their difference is the halves' error itself, e ~ u_halves - u_full (stiff components are damped
// by both alike).
inline constexpr double kStartErrorFactor = 1.0;

struct StepDecision {
  bool accept = false;
  double next = 0.0;  // the next step (or the retry's, where rejected)
};

// The step after an error estimate `error` (a weighted RMS norm: 1 is the tolerance) of a step h of
// a method of local order `order` + 1: accepted where error <= 1; the next step
// h * clamp(kStepSafety * error^(-1/(order + 1)), kMinStepFactor, kMaxStepGrowth), within
// [min_step, max_step]. A retry is never longer than the rejected step.
StepDecision decide_step(double error, double h, int order, double min_step, double max_step);

// Whether a factorisation of (c0 / h) B + J made at coefficient `factorised` still serves a step
// whose coefficient is `now`.
bool keeps_factorisation(double now, double factorised);

}  // namespace keller
