// The incompressible neo-Hookean wall alone: the total-Lagrangian weak form gives zero residual
// for a rigid rotation, the analytic stress for a homogeneous isochoric stretch, keeps the
// solid's area to rounding under load, and its Jacobian (follower loads included) and
// parameter derivatives (Pe, and t through the reference geometry) match finite differences.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/Newton.hpp"
#include "problems/channel/WallProblem.hpp"
#include "support/TestSupport.hpp"

using namespace keller;

namespace {

WallOptions small_wall() {
  WallOptions o;
  o.mesh = ChannelMeshSpec::preset("M1");  // 20 x 4 wall elements
  o.geometry.thickness = 0.4;
  return o;
}

// Sets positions x = f(X) and pi = pi0 on every solid node and element.
template <class Map>
Vector state(const WallProblem& p, Map f, double pi0) {
  Vector u = Vector::Zero(p.size());
  const int fx = p.dofs().field_index("position"), fp = p.dofs().field_index("solid_pressure");
  for (int n = 0; n < p.mesh().num_nodes(); ++n) {
    const auto X = p.wall().reference().at(n, p.parameters().values());
    const auto x = f(X);
    u[p.dofs().node_dof(fx, n, 0)] = x[0];
    u[p.dofs().node_dof(fx, n, 1)] = x[1];
  }
  for (int e = 0; e < p.mesh().num_elements(); ++e) u[p.dofs().element_dof(fp, e, 0, 0)] = pi0;
  return u;
}

}  // namespace

TEST(Solid, RigidRotationGivesZeroResidual) {
  WallOptions o = small_wall();
  o.Pe = 0.0;
  WallProblem p(o);
  const double a = 0.7, c = std::cos(a), s = std::sin(a);
  // B = I, so sigma = I - pi I vanishes for pi = 1
  const Vector u = state(
      p,
      [&](std::array<double, 2> X) {
        return std::array<double, 2>{c * X[0] - s * X[1] + 3.0, s * X[0] + c * X[1] - 2.0};
      },
      1.0);
  Vector F;
  ASSERT_TRUE(p.assembler().weak_residual(u, F).is_ok());
  EXPECT_LT(F.cwiseAbs().maxCoeff(), 1e-13);
  // and the stress-free state needs pi = 1 exactly: another pi gives a residual
  const Vector u2 = state(
      p, [&](std::array<double, 2> X) { return X; }, 0.5);
  ASSERT_TRUE(p.assembler().weak_residual(u2, F).is_ok());
  EXPECT_GT(F.cwiseAbs().maxCoeff(), 1e-3);
}

TEST(Solid, HomogeneousStretchGivesTheAnalyticStress) {
  WallOptions o = small_wall();
  o.Pe = 0.0;
  WallProblem p(o);
  const double lam = 1.3, pi0 = 0.4, X0 = 7.0, t = 0.4;
  // x = lam (X - X0) + X0, y = (Y - 1) / lam + 1: J = 1; sigma_xx = lam^2 - pi0, sigma_yy = lam^-2 - pi0
  const Vector u = state(
      p,
      [&](std::array<double, 2> X) {
        return std::array<double, 2>{lam * (X[0] - X0) + X0, (X[1] - 1.0) / lam + 1.0};
      },
      pi0);
  Vector F;
  ASSERT_TRUE(p.assembler().weak_residual(u, F).is_ok());
  const int fx = p.dofs().field_index("position");
  const auto right = p.mesh().boundary_nodes("wall_right"), left = p.mesh().boundary_nodes("wall_left");
  const auto top = p.mesh().boundary_nodes("wall_top"), bottom = p.mesh().boundary_nodes("interface");
  auto on = [](const std::vector<int>& v, int n) { return std::binary_search(v.begin(), v.end(), n); };
  double fright = 0, fleft = 0, interior = 0;
  for (int n = 0; n < p.mesh().num_nodes(); ++n) {
    const double rx = F[p.dofs().node_dof(fx, n, 0)], ry = F[p.dofs().node_dof(fx, n, 1)];
    if (on(right, n)) fright += rx;
    if (on(left, n)) fleft += rx;
    if (!on(right, n) && !on(left, n) && !on(top, n) && !on(bottom, n))
      interior = std::max({interior, std::abs(rx), std::abs(ry)});
  }
  // the resultant on a side is sigma_xx times the deformed height t / lam
  const double expected = (lam * lam - pi0) * t / lam;
  EXPECT_NEAR(fright, expected, 1e-12);
  EXPECT_NEAR(fleft, -expected, 1e-12);
  EXPECT_LT(interior, 1e-13);
  // sigma_yy acts on the top and bottom: resultant (lam^-2 - pi0) * deformed length 5 lam
  double ftop = 0;
  for (int n : top) ftop += F[p.dofs().node_dof(fx, n, 1)];
  EXPECT_NEAR(ftop, (1.0 / (lam * lam) - pi0) * 5.0 * lam, 1e-12);
  // the constraint rows vanish where J = 1
  const int fp = p.dofs().field_index("solid_pressure");
  double cons = 0;
  for (int e = 0; e < p.mesh().num_elements(); ++e)
    for (int k = 0; k < 3; ++k) cons = std::max(cons, std::abs(F[p.dofs().element_dof(fp, e, k, 0)]));
  EXPECT_LT(cons, 1e-13);
}

TEST(Solid, AreaIsConservedUnderLoadAndTheWallIsSymmetric) {
  WallOptions o = small_wall();
  o.Pe = 0.004;  // pushes the wall into the channel by about a quarter of its width
  WallProblem p(o);
  Vector u = p.initial_guess();
  NewtonSolver newton(p);
  const NewtonResult r = newton.solve(u, [](const NewtonIteration& it) { print_newton_row(it); });
  ASSERT_TRUE(r.converged()) << r.status.describe();
  std::vector<double> obs;
  ASSERT_TRUE(p.observables(u, obs).is_ok());
  const double dx = obs[0], dy = obs[1], dA = obs[2];
  std::printf("deflection (%.3e, %.6f), area change %.3e of %.3f, min det F %.4f\n", dx, dy, dA,
              p.wall().reference_area(), obs[3]);
  EXPECT_LT(dy, -0.05);                                        // a real, large deflection
  EXPECT_LT(std::abs(dA), 1e-10 * p.wall().reference_area());  // exact incompressibility per element
  EXPECT_LT(std::abs(dx), 1e-8);                               // left-right symmetry of the problem
  EXPECT_GT(obs[3], 0.0);
}

TEST(Solid, JacobianAndParameterDerivativesMatchFiniteDifferences) {
  WallOptions o = small_wall();
  o.mesh = ChannelMeshSpec::preset("M1");
  o.mesh.nx_deformable = 6;
  o.mesh.ny_solid = 2;
  o.Pe = 0.03;
  o.Pin = 0.01;
  WallProblem p(o);
  // a smooth large deformation plus noise, and a non-trivial pressure
  Vector u = state(
      p,
      [](std::array<double, 2> X) {
        const double s = (X[0] - 7.0) / 5.0;
        return std::array<double, 2>{X[0] + 0.1 * std::sin(3 * s) * (X[1] - 1.0),
                                     X[1] - 0.3 * std::sin(M_PI * s) * (1.4 - X[1])};
      },
      0.2);
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> d(-0.01, 0.01);
  for (int i = 0; i < u.size(); ++i) u[i] += d(gen);
  const test::JacobianCheck c = test::check_problem_jacobian(p, u);
  std::printf("Jacobian: max relative error %.2e at (%d, %d)\n", c.max_relative_error, c.worst_row, c.worst_col);
  EXPECT_LT(c.max_relative_error, 1e-6);
  for (const char* name : {"t", "Pe", "Pin"}) {
    const double e = test::check_parameter_derivative(p, p.parameters().index(name), u);
    std::printf("dF/d%s: max relative error %.2e\n", name, e);
    EXPECT_LT(e, 1e-6) << name;
  }
}
