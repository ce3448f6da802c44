// Hopf curves by the minimally augmented system (continuation/curves/HopfCurveProblem): the Brusselator,
// whose Hopf curve b = 1 + a^2 with omega = a is known in closed form on every grid, the augmented
// Jacobian against differences of its residual, and the codimension-two points where a Hopf curve
// meets a fold curve (Bogdanov-Takens, fold-Hopf) on normal forms whose points are known exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <optional>
#include <string>

#include "continuation/Continuation.hpp"
#include "continuation/curves/HopfCurveProblem.hpp"
#include "continuation/output/BranchFile.hpp"
#include "problems/analytic/Brusselator1DProblem.hpp"
#include "runs/NormalFormObserver.hpp"
#include "support/TestProblems.hpp"
#include "support/TestSupport.hpp"

using namespace keller;

namespace {

NewtonOptions tight() {
  NewtonOptions n;
  n.residual_tolerance = 1e-12;  // two orders below the 1e-10 the curves are checked to
  return n;
}

// The Bogdanov-Takens normal form x' = y, y' = beta1 + beta2 x + x^2 - x y (F = -rhs, B = I).
// Equilibria (x, 0) with x^2 + beta2 x + beta1 = 0; the Jacobian of the right-hand side
// [0 1; beta2 + 2x, -x] has trace -x and determinant -(beta2 + 2x): Hopf points where x = 0, so
// beta1 = 0, with omega^2 = -beta2 (beta2 < 0); folds on beta1 = beta2^2 / 4; both meet at the
// Bogdanov-Takens point beta1 = beta2 = 0, where omega = 0. (Exact Jacobians: the Hopf condition is
// that of the J it is given.)
test::FunctionProblem bogdanov_takens(double beta1, double beta2) {
  return test::FunctionProblem(
      "bogdanov-takens", 2, {{"beta1", beta1}, {"beta2", beta2}},
      [](const Vector& u, const Vector& p) {
        const double x = u[0], y = u[1];
        return Vector(Eigen::Vector2d(-y, -(p[0] + p[1] * x + x * x - x * y)));
      },
      [](const Vector& u, const Vector& p) {
        Eigen::Matrix2d J;
        J << 0.0, -1.0, -(p[1] + 2.0 * u[0] - u[1]), u[0];
        return Eigen::MatrixXd(J);
      },
      [](int k, const Vector& u, const Vector&) { return Vector(Eigen::Vector2d(0.0, k == 0 ? -1.0 : -u[0])); });
}

// The fold-Hopf (zero-Hopf) normal form x' = beta1 + x^2, (y, z)' = R (y, z) with
// R = [beta2 + x, -omega0; omega0, beta2 + x] (F = -rhs, B = I). Equilibria (x, 0, 0) with
// x^2 = -beta1; the pair beta2 + x +- i omega0 crosses the imaginary axis where beta2 = -x, with
// omega = omega0; the real eigenvalue 2x crosses zero at x = 0. The Hopf curve beta1 = -beta2^2
// (x = -beta2) passes through the fold-Hopf point beta1 = beta2 = 0, where det J changes sign.
constexpr double kOmega0 = 2.0;
test::FunctionProblem fold_hopf(double beta1, double beta2) {
  return test::FunctionProblem(
      "fold-hopf", 3, {{"beta1", beta1}, {"beta2", beta2}},
      [](const Vector& u, const Vector& p) {
        const double x = u[0], y = u[1], z = u[2], r = p[1] + x;
        return Vector(Eigen::Vector3d(-(p[0] + x * x), -(r * y - kOmega0 * z), -(kOmega0 * y + r * z)));
      },
      [](const Vector& u, const Vector& p) {
        const double x = u[0], y = u[1], z = u[2], r = p[1] + x;
        Eigen::Matrix3d J;
        J << -2.0 * x, 0.0, 0.0, -y, -r, kOmega0, -z, -kOmega0, -r;
        return Eigen::MatrixXd(J);
      },
      [](int k, const Vector& u, const Vector&) {
        return Vector(k == 0 ? Eigen::Vector3d(-1.0, 0.0, 0.0) : Eigen::Vector3d(0.0, -u[1], -u[2]));
      });
}

// A Bautin problem with a known first Lyapunov coefficient. In Z = x + i y and a third unknown w:
//   Z' = (mu - nu^2 + i omega0) Z + (nu + i b) Z |Z|^2 + gamma Z w + delta conj(Z) w,
//   w' = -kappa w + |Z|^2 + Re Z^2     (F = -rhs, B = I).
// The origin is an equilibrium; its pair mu - nu^2 +- i omega0 crosses the axis on the Hopf curve
// mu = nu^2, omega = omega0. On the centre manifold w = |Z|^2 / kappa + Re(alpha Z^2) with
// alpha = 1 / (kappa + 2 i omega0) (the h11 and h20 terms), so the resonant cubic coefficient is
// C = nu + i b + gamma / kappa + delta alpha / 2. With the eigenvector q = (1, -i, 0) (Z = 2 z),
// c1 = 4 C, and with q of unit norm (|q|^2 = 2) l1 = 2 Re C / omega0: zero at the Bautin point
// nu_B = -gamma / kappa - delta kappa / (2 (kappa^2 + 4 omega0^2)).
struct BautinConstants {
  double omega0 = 1.5, b = 0.3, gamma = 0.6, delta = 1.0, kappa = 2.0;
  double re_c(double nu) const {
    return nu + gamma / kappa + delta * kappa / (2.0 * (kappa * kappa + 4.0 * omega0 * omega0));
  }
  double unit_l1(double nu) const { return 2.0 * re_c(nu) / omega0; }
};
test::FunctionProblem bautin(double mu, double nu, const BautinConstants& k = {}) {
  auto rhs = [k](const Vector& u, const Vector& p) {
    const double x = u[0], y = u[1], w = u[2], r2 = x * x + y * y, m = p[0] - p[1] * p[1];
    return Eigen::Vector3d(m * x - k.omega0 * y + (p[1] * x - k.b * y) * r2 + (k.gamma + k.delta) * x * w,
                           k.omega0 * x + m * y + (k.b * x + p[1] * y) * r2 + (k.gamma - k.delta) * y * w,
                           -k.kappa * w + r2 + x * x - y * y);
  };
  return test::FunctionProblem(
      "bautin", 3, {{"mu", mu}, {"nu", nu}}, [rhs](const Vector& u, const Vector& p) { return Vector(-rhs(u, p)); },
      [k](const Vector& u, const Vector& p) {
        const double x = u[0], y = u[1], w = u[2], r2 = x * x + y * y, m = p[0] - p[1] * p[1], c = p[1];
        const double gp = k.gamma + k.delta, gm = k.gamma - k.delta;
        Eigen::Matrix3d A;
        A << m + c * r2 + 2.0 * x * (c * x - k.b * y) + gp * w, -k.omega0 - k.b * r2 + 2.0 * y * (c * x - k.b * y),
            gp * x, k.omega0 + k.b * r2 + 2.0 * x * (k.b * x + c * y),
            m + c * r2 + 2.0 * y * (k.b * x + c * y) + gm * w, gm * y, 4.0 * x, 0.0, -k.kappa;
        return Eigen::MatrixXd(-A);
      },
      [](int j, const Vector& u, const Vector& p) {
        const double x = u[0], y = u[1], r2 = x * x + y * y;
        if (j == 0) return Vector(-Eigen::Vector3d(x, y, 0.0));
        return Vector(-Eigen::Vector3d(-2.0 * p[1] * x + x * r2, -2.0 * p[1] * y + y * r2, 0.0));
      });
}

// The Brusselator's options: intervals, a, b and D_v (D_u = 1).
Brusselator1DOptions brusselator(int intervals, double a, double b, double D_v = 1.0) {
  Brusselator1DOptions o;
  o.intervals = intervals;
  o.a = a;
  o.b = b;
  o.D_v = D_v;
  return o;
}

// A Hopf curve traced from U (start() done) in o.parameter, with its borders following it; with
// `inner` (the curve's problem, its p1 beta1), the normal forms of its codimension-two points
// attached as keller trace does (NormalFormObserver::for_curve).
struct Traced {
  ContinuationResult result;
  test::RecordingObserver rec;
};
Traced trace(HopfCurveProblem& curve, const Vector& U, const ContinuationOptions& o, Problem* inner = nullptr) {
  Continuation cont(curve, o, tight());
  Traced t;
  std::optional<NormalFormObserver> forms;
  if (inner)
    forms.emplace(NormalFormObserver::for_curve(t.rec, *inner, inner->parameters().index("beta1"),
                                                inner->parameters().index(o.parameter), curve.observable_names().size(),
                                                {}));
  HopfCurveProblem::BorderUpdate borders(curve, forms ? static_cast<BranchObserver&>(*forms) : t.rec);
  t.result = cont.run(U, borders);
  return t;
}

// A column of the normal form attached to a point of a Hopf curve of `inner`, whose observables add
// p1 and omega to the inner problem's.
double normal_form_column(const BranchPoint& point, const Problem& inner, const std::string& name) {
  const std::vector<std::string> columns = normal_form_columns(inner.observable_names());
  EXPECT_EQ(point.normal_form.size(), columns.size() + 2);
  const auto it = std::find(columns.begin(), columns.end(), name);
  return it == columns.end() || point.normal_form.size() != columns.size() + 2
             ? NAN
             : point.normal_form[static_cast<size_t>(it - columns.begin())];
}

// Options for a curve in `parameter` from `lower` to `upper` with short steps (a few points between
// its codimension-two points) and events located to 1e-8.
ContinuationOptions curve_options(const std::string& parameter, double lower, double upper) {
  ContinuationOptions o;
  o.parameter = parameter;
  o.stop.lower = lower;
  o.stop.upper = upper;
  o.step.initial = 0.05;
  o.step.max = 0.1;
  o.events.tolerance = 1e-8;
  return o;
}

// The located points of a kind with a label.
std::vector<const BranchPoint*> labelled(const test::RecordingObserver& rec, PointKind kind, const std::string& label) {
  std::vector<const BranchPoint*> out;
  for (const BranchPoint* p : rec.of_kind(kind))
    if (p->label == label) out.push_back(p);
  return out;
}

}  // namespace

// The Brusselator (32 intervals): the uniform state's Hopf point b = 1 + a^2 (omega = a), from a
// perturbed start at a = 2 continued in a to 3: every point on b = 1 + a^2 and omega = a to 1e-8
// (the curve is exact on the grid; Newton's tolerance 1e-12), the state uniform (a, b / a).
TEST(HopfCurve, BrusselatorHopfCurveIsBEqualsOnePlusASquared) {
  Brusselator1DProblem p(brusselator(32, 2.0, 5.0));
  HopfCurveProblem curve(p, "b");
  const int n = p.size();
  Vector U = curve.state(p.initial_guess() + Vector::Constant(n, 1e-3), 5.0 + 1e-3, 2.0 + 1e-3);
  ASSERT_TRUE(curve.start(U, ComplexVector(), tight()).is_ok());
  EXPECT_NEAR(U[n], 5.0, 1e-10);
  EXPECT_NEAR(U[n + 1], 2.0, 1e-10);
  ContinuationOptions o = curve_options("a", 2.0, 3.0);
  o.step.max = 0.2;
  o.events.stops = {2.5};
  const auto [r, rec] = trace(curve, U, o);
  ASSERT_EQ(r.code, StopCode::UpperBound) << r.reason;
  ASSERT_GT(rec.points.size(), 5u);
  double worst_b = 0.0, worst_omega = 0.0;
  for (const BranchPoint& q : rec.points) {
    const double a = q.lambda, b = q.u[n], omega = q.u[n + 1];
    worst_b = std::max(worst_b, std::abs(b - (1.0 + a * a)));
    worst_omega = std::max(worst_omega, std::abs(omega - a));
    EXPECT_NEAR(b, 1.0 + a * a, 1e-8) << "a = " << a;
    EXPECT_NEAR(omega, a, 1e-8) << "a = " << a;
    EXPECT_NEAR(q.u[0], a, 1e-8) << "a = " << a;      // u at the first node
    EXPECT_NEAR(q.u[1], b / a, 1e-8) << "a = " << a;  // v at the first node
    EXPECT_NEAR(q.observables.back(), omega, 0.0);    // omega is the last observable
  }
  std::cout << std::setprecision(3) << rec.points.size() << " points, largest |b - (1 + a^2)| = " << worst_b
            << ", |omega - a| = " << worst_omega << "; " << r.factorisations << " factorisations\n";
  EXPECT_EQ(rec.of_kind(PointKind::Requested).size(), 1u);
  EXPECT_NEAR(rec.points.back().lambda, 3.0, 1e-12);
  EXPECT_TRUE(labelled(rec, PointKind::Event, "bogdanov-takens").empty());
  EXPECT_TRUE(labelled(rec, PointKind::Event, "fold-hopf").empty());
}

// The bordered Jacobian [J F_b 0; Re g_u^T ...; Im g_u^T ...] of the Hopf curve (g's derivatives by
// differences of J and dF/dp along v, g_omega exact), assembled, and dF/da, against central
// differences of the augmented residual off the curve (a state that is not uniform, b and omega
// off their Hopf values), to 1e-6 of the largest entry of each row (differences of differences,
// steps 1e-5 and 1e-7).
TEST(HopfCurve, AugmentedJacobianMatchesDifferencesOfItsResidual) {
  Brusselator1DProblem p(brusselator(8, 1.5, 3.2, 0.7));
  HopfCurveProblem curve(p, "b");
  const int n = p.size();
  Vector u = p.initial_guess();
  for (int i = 0; i < n; ++i) u[i] += 0.1 * std::sin(0.9 * i);
  const Vector U = curve.state(u, 3.2, 1.4);
  ASSERT_TRUE(curve.set_borders(U, ComplexVector()).is_ok());
  const test::JacobianCheck check = test::check_problem_jacobian(curve, U, 1e-5);
  std::cout << "largest relative error of the augmented Jacobian " << check.max_relative_error << " (row "
            << check.worst_row << ", column " << check.worst_col << ")\n";
  EXPECT_LT(check.max_relative_error, 1e-6);
  BorderedJacobian B;
  Vector F;
  ASSERT_TRUE(curve.bordered_jacobian(U, F, B).is_ok());
  EXPECT_GT(B.C.norm(), 1e-3 * B.D.norm());  // g depends on u: the rows are there
  const double dp = test::check_parameter_derivative(curve, p.parameters().index("a"), U, 1e-7);
  std::cout << "dF/da: largest relative error " << dp << "\n";
  EXPECT_LT(dp, 1e-6);
}

// The Bogdanov-Takens normal form: the Hopf curve beta1 = 0, omega = sqrt(-beta2) continued in
// beta2 from -1 up to the Bogdanov-Takens point, where omega passes through zero and the curve
// turns back in beta2 (omega < 0 is the same curve). Every point on beta1 = 0 and
// omega^2 = -beta2 to 1e-10; the point located where omega changes sign at beta2 = 0 to 1e-8
// (beta2 = -omega^2 there, so omega to 1e-4, the square root), beta1 = 0. Its normal form
// (NormalFormObserver::for_curve, as keller trace attaches it): the quadratic terms x^2 - x y
// give a = 1, b = -1 with q0 = (1, 0), to 1e-6 (J at the located point has the pair +-i omega,
// |omega| below 1e-4, not yet the Jordan block).
TEST(HopfCurve, BogdanovTakensWhereOmegaVanishes) {
  test::FunctionProblem p = bogdanov_takens(0.0, -1.0);
  HopfCurveProblem curve(p, "beta1");
  Vector U = curve.state(Eigen::Vector2d(1e-3, -1e-3), 1e-3, 1.0 + 1e-3);
  ASSERT_TRUE(curve.start(U, ComplexVector(), tight()).is_ok());
  EXPECT_NEAR(U[3], 1.0, 1e-10);
  const auto [r, rec] = trace(curve, U, curve_options("beta2", -1.0, 0.5), &p);
  ASSERT_EQ(r.code, StopCode::LowerBound) << r.reason;
  for (const BranchPoint& q : rec.points) {
    EXPECT_NEAR(q.u[2], 0.0, 1e-10) << "beta2 = " << q.lambda;
    EXPECT_NEAR(q.u[3] * q.u[3], -q.lambda, 1e-10) << "beta2 = " << q.lambda;
  }
  const auto bt = labelled(rec, PointKind::Event, "bogdanov-takens");
  ASSERT_EQ(bt.size(), 1u) << r.reason;
  std::cout << std::setprecision(3) << "Bogdanov-Takens at beta2 = " << bt[0]->lambda << ", beta1 = " << bt[0]->u[2]
            << ", omega = " << bt[0]->u[3] << "\n";
  EXPECT_NEAR(bt[0]->lambda, 0.0, 1e-8);
  EXPECT_NEAR(bt[0]->u[2], 0.0, 1e-10);
  EXPECT_NEAR(bt[0]->u[3], 0.0, 1e-4);
  auto column = [&](const char* name) { return normal_form_column(*bt[0], p, name); };
  EXPECT_EQ(normal_form_types()[static_cast<size_t>(column("type"))], "Bogdanov-Takens");
  EXPECT_NEAR(column("a"), 1.0, 1e-6);
  EXPECT_NEAR(column("b"), -1.0, 1e-6);
  // the curve turns in beta2 there, and comes back on the side omega < 0
  const auto turns = rec.of_kind(PointKind::Fold);
  ASSERT_EQ(turns.size(), 1u);
  EXPECT_EQ(turns[0]->label, "max");
  EXPECT_NEAR(turns[0]->lambda, 0.0, 1e-8);
  EXPECT_NEAR(rec.points.back().u[3], -1.0, 1e-10);
  // beta1 stays 0: its part of the tangent is rounding (1e-20 of either sign), no turn of it
  EXPECT_TRUE(labelled(rec, PointKind::Event, "beta1 max").empty());
  EXPECT_TRUE(labelled(rec, PointKind::Event, "beta1 min").empty());
}

// The same curve with the "bautin" monitor of a Lyapunov coefficient that cannot be computed for
// |omega| < 0.3 (as the normal form's, whose pair merges at the Bogdanov-Takens point): the monitor
// is NaN there (a partial monitor), every point and the Bogdanov-Takens point are still computed,
// and no Bautin point is sought across the NaNs.
TEST(HopfCurve, AnUndefinedLyapunovCoefficientNearOmegaZeroLeavesTheCurveWhole) {
  test::FunctionProblem p = bogdanov_takens(0.0, -1.0);
  HopfCurveProblem curve(p, "beta1");
  const HopfCurveProblem::LyapunovCoefficient l1 = unit_mode_lyapunov_coefficient({});
  curve.set_lyapunov_coefficient(
      [&](Problem& inner, int p1, const Vector& u, double omega, const ComplexVector& mode, double& value) {
        if (std::abs(omega) < 0.3) return Status{StatusCode::InvalidState, "no complex pair near the Hopf point"};
        return l1(inner, p1, u, omega, mode, value);
      });
  ASSERT_EQ(curve.partial_monitors(), std::vector<int>{static_cast<int>(curve.monitor_names().size()) - 1});
  Vector U = curve.state(Eigen::Vector2d(1e-3, -1e-3), 1e-3, 1.0 + 1e-3);
  ASSERT_TRUE(curve.start(U, ComplexVector(), tight()).is_ok());
  const auto [r, rec] = trace(curve, U, curve_options("beta2", -1.0, 0.5), &p);
  ASSERT_EQ(r.code, StopCode::LowerBound) << r.reason;
  int undefined = 0;
  for (const BranchPoint& q : rec.points) {
    EXPECT_EQ(std::isnan(q.monitors.back()), std::abs(q.u[3]) < 0.3) << "omega = " << q.u[3];
    undefined += std::isnan(q.monitors.back());
  }
  EXPECT_GE(undefined, 2);
  const auto bt = labelled(rec, PointKind::Event, "bogdanov-takens");
  ASSERT_EQ(bt.size(), 1u);
  EXPECT_NEAR(bt[0]->lambda, 0.0, 1e-8);
  EXPECT_TRUE(labelled(rec, PointKind::Event, "bautin").empty());
}

// The fold-Hopf normal form: the Hopf curve beta1 = -beta2^2, omega = omega0 continued in beta2
// from -0.5 to 0.5 through the fold-Hopf point (0, 0), where the real eigenvalue 2x = -2 beta2
// crosses zero. Every point on the curve to 1e-10; the point located where the fold test function
// of J changes sign at beta2 = 0 to 1e-8, beta1 = 0 to 1e-10, omega = omega0. (J is singular
// there: the block elimination falls back to the whole matrix.)
TEST(HopfCurve, FoldHopfWhereDetJChangesSign) {
  test::FunctionProblem p = fold_hopf(-0.25, -0.5);
  HopfCurveProblem curve(p, "beta1");
  Vector U = curve.state(Eigen::Vector3d(0.5 + 1e-3, 1e-3, -1e-3), -0.25 + 1e-3, kOmega0 + 1e-3);
  ASSERT_TRUE(curve.start(U, ComplexVector(), tight()).is_ok());
  const auto [r, rec] = trace(curve, U, curve_options("beta2", -0.5, 0.5), &p);
  ASSERT_EQ(r.code, StopCode::UpperBound) << r.reason;
  for (const BranchPoint& q : rec.points) {
    const double b2 = q.lambda;
    EXPECT_NEAR(q.u[0], -b2, 1e-10) << "beta2 = " << b2;
    EXPECT_NEAR(q.u[3], -b2 * b2, 1e-10) << "beta2 = " << b2;
    EXPECT_NEAR(q.u[4], kOmega0, 1e-10) << "beta2 = " << b2;
  }
  const auto zh = labelled(rec, PointKind::Event, "fold-hopf");
  ASSERT_EQ(zh.size(), 1u) << r.reason;
  std::cout << std::setprecision(3) << "fold-Hopf at beta2 = " << zh[0]->lambda << ", beta1 = " << zh[0]->u[3]
            << ", omega = " << zh[0]->u[4] << "\n";
  EXPECT_NEAR(zh[0]->lambda, 0.0, 1e-8);
  EXPECT_NEAR(zh[0]->u[3], 0.0, 1e-10);
  EXPECT_NEAR(zh[0]->u[4], kOmega0, 1e-10);
  EXPECT_TRUE(labelled(rec, PointKind::Event, "bogdanov-takens").empty());
  // its normal form, as keller trace attaches it: x^2 and the pair's (beta2 + x) give g200 = 2,
  // g011 = 0, g110 = 1 (q1 = (0, 1, -i) / sqrt 2); at the located point x = -beta2 ~ 1e-8
  auto column = [&](const char* name) { return normal_form_column(*zh[0], p, name); };
  EXPECT_EQ(normal_form_types()[static_cast<size_t>(column("type"))], "fold-Hopf");
  EXPECT_NEAR(column("a"), 2.0, 1e-6);
  EXPECT_NEAR(column("b"), 0.0, 1e-6);
  EXPECT_NEAR(column("c1_re"), 1.0, 1e-6);
  EXPECT_NEAR(column("c1_im"), 0.0, 1e-6);
  EXPECT_NEAR(column("omega"), kOmega0, 1e-10);
}

// The Bautin problem's Hopf curve mu = nu^2 continued in nu from -1 to 0.5 with the first Lyapunov
// coefficient of keller trace's curves (runs/NormalFormObserver: the normal form at every point,
// q of unit norm): the "bautin" column equals 2 Re C / omega0 at every point, and the point located
// where it changes sign is nu_B of the closed form, with mu = nu_B^2 and omega = omega0. The
// problem is cubic, so the difference derivatives are exact but for rounding (relative 1e-9 at
// the D^3 step 1e-2): the values to 1e-7, the point to the locator's 1e-8.
TEST(HopfCurve, BautinPointWhereTheFirstLyapunovCoefficientChangesSign) {
  const BautinConstants k;
  test::FunctionProblem p = bautin(1.0, -1.0, k);
  HopfCurveProblem curve(p, "mu");
  curve.set_lyapunov_coefficient(unit_mode_lyapunov_coefficient({}));
  ASSERT_EQ(curve.monitor_names().back(), "bautin");
  Vector U = curve.state(Eigen::Vector3d(1e-3, -1e-3, 1e-3), 1.0 + 1e-3, k.omega0 + 1e-3);
  ASSERT_TRUE(curve.start(U, ComplexVector(), tight()).is_ok());
  const auto [r, rec] = trace(curve, U, curve_options("nu", -1.0, 0.5));
  ASSERT_EQ(r.code, StopCode::UpperBound) << r.reason;
  for (const BranchPoint& q : rec.points) {
    const double nu = q.lambda;
    EXPECT_NEAR(q.u[3], nu * nu, 1e-10) << "nu = " << nu;
    EXPECT_NEAR(q.u[4], k.omega0, 1e-10) << "nu = " << nu;
    EXPECT_NEAR(q.monitors.back(), k.unit_l1(nu), 1e-7) << "nu = " << nu;
  }
  const auto gh = labelled(rec, PointKind::Event, "bautin");
  ASSERT_EQ(gh.size(), 1u) << r.reason;
  const double nu_b = -k.gamma / k.kappa - k.delta * k.kappa / (2.0 * (k.kappa * k.kappa + 4.0 * k.omega0 * k.omega0));
  std::cout << std::setprecision(10) << "Bautin at nu = " << gh[0]->lambda << " (closed form " << nu_b << ")\n";
  EXPECT_NEAR(gh[0]->lambda, nu_b, 1e-8);
  EXPECT_NEAR(gh[0]->u[3], nu_b * nu_b, 1e-8);
  EXPECT_NEAR(gh[0]->u[4], k.omega0, 1e-10);
  EXPECT_TRUE(labelled(rec, PointKind::Event, "bogdanov-takens").empty());
  EXPECT_TRUE(labelled(rec, PointKind::Event, "fold-hopf").empty());
}
