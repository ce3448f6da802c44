// The fully coupled collapsible channel: the Jacobian (flow, mesh equations, solid, the shape
// derivatives of the flow residuals with respect to node positions, and the interface
// reaction moved onto the solid's rows) and every dF/dp (Gamma, Wi, t, Pe, ...) against central
// differences, for each fluid, at a perturbed state on a coarse mesh. Fails above 1e-6.
#include <gtest/gtest.h>

#include <iostream>
#include <random>

#include "problems/channel/CollapsibleChannelProblem.hpp"
#include "support/TestSupport.hpp"

using namespace keller;

namespace {

CollapsibleOptions coarse_options(FluidModel model, bool log_form) {
  CollapsibleOptions o;
  o.mesh.name = "custom";
  o.mesh.nx_upstream = 1;
  o.mesh.nx_deformable = 3;
  o.mesh.nx_downstream = 1;
  o.mesh.ny_fluid = 2;
  o.mesh.ny_solid = 1;
  o.Gamma = 0.05;
  o.Pe = 0.3;
  o.fluid.model = model;
  o.fluid.log_conformation = log_form;
  o.fluid.Wi = 0.7;
  o.fluid.beta = 0.3;
  o.fluid.constants.b = 20.0;
  o.fluid.Re = 0.01;  // inertia on, so dF/dRe is checked too (and Re = 0 sits on its bound)
  o.fluid.inertia = true;
  o.fluid.profile = model == FluidModel::Newtonian ? ProfileKind::Parabolic : ProfileKind::FullyDeveloped;
  return o;
}

// The initial guess with every unknown perturbed (the conformation drawn anew, positive definite).
Vector perturbed_state(CollapsibleChannelProblem& problem, FluidModel model, bool log_form) {
  Vector u = problem.initial_guess();
  const DofMap& d = problem.dofs();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1, 1);
  const int fx = d.field_index("position");
  for (int n = 0; n < problem.mesh().num_nodes(); ++n)
    for (int c = 0; c < 2; ++c) u[d.node_dof(fx, n, c)] += 0.03 * U(rng);
  for (int f = 0; f < d.num_fields(); ++f) {
    if (d.field(f).name == "position" || d.field(f).name.rfind("conformation", 0) == 0) continue;
    for (int n = 0; n < problem.mesh().num_nodes(); ++n)
      for (int c = 0; c < d.num_components(f); ++c)
        if (d.node_dof(f, n, c) >= 0) u[d.node_dof(f, n, c)] += 0.05 * U(rng);
  }
  if (model != FluidModel::Newtonian)
    for (int fm = 0; fm < d.num_fields(); ++fm) {
      if (d.field(fm).name.rfind("conformation", 0) != 0) continue;  // every mode's
      for (int n = 0; n < problem.mesh().num_nodes(); ++n)
        for (int k = 0; k < d.num_components(fm); ++k)
          if (d.node_dof(fm, n, k) >= 0)
            u[d.node_dof(fm, n, k)] = log_form ? 0.4 * U(rng) : (k == 1 ? 0.3 * U(rng) : 1.2 + 0.4 * U(rng));
    }
  return u;
}

// Two modes of different times and shares (the second, PolymerModeKernel, on the moving mesh).
CollapsibleOptions two_mode_options(FluidModel model, bool log_form) {
  CollapsibleOptions o = coarse_options(model, log_form);
  o.fluid.modes = {{"slow", 1.3, 0.6}, {"fast", 0.2, 0.4}};
  o.fluid.constants.alpha = 0.3;  // inside its range, so that dF/dalpha has both sides
  return o;
}

void check(FluidModel model, bool log_form, bool two_modes = false) {
  SCOPED_TRACE(std::string(to_string(model)) + (log_form ? " log" : "") + (two_modes ? " two modes" : ""));
  CollapsibleChannelProblem problem(two_modes ? two_mode_options(model, log_form) : coarse_options(model, log_form));
  const Vector u = perturbed_state(problem, model, log_form);
  const DofMap& d = problem.dofs();
  const auto jc = test::check_problem_jacobian(problem, u);
  std::cout << to_string(model) << (log_form ? " log" : "") << ": " << problem.size()
            << " unknowns, Jacobian max relative error " << jc.max_relative_error << " (row "
            << d.describe(jc.worst_row) << ", column " << d.describe(jc.worst_col) << ")\n";
  EXPECT_LT(jc.max_relative_error, 1e-6);
  for (const Parameter& p : problem.parameters().list()) {
    const double e = test::check_parameter_derivative(problem, problem.parameters().index(p.name), u);
    std::cout << "  dF/d" << p.name << ": " << e << "\n";
    EXPECT_LT(e, 1e-6) << "dF/d" << p.name;
  }
}

}  // namespace

TEST(CollapsibleJacobian, Newtonian) { check(FluidModel::Newtonian, false); }
TEST(CollapsibleJacobian, OldroydB) { check(FluidModel::OldroydB, false); }
TEST(CollapsibleJacobian, OldroydBLogConformation) { check(FluidModel::OldroydB, true); }
TEST(CollapsibleJacobian, FeneP) { check(FluidModel::FeneP, false); }
TEST(CollapsibleJacobian, Owens) { check(FluidModel::Owens, false); }
TEST(CollapsibleJacobian, TwoModeGiesekusInBothForms) {
  check(FluidModel::Giesekus, false, true);
  check(FluidModel::Giesekus, true, true);
}

// The observable min_m1 has the monitor's gradient (a branch that stops on it lands its last
// step on the zero): the same vector, and against central differences of the observable along a
// random direction at a state where the minimum's node is unique (the perturbed conformation).
// Step 1e-6: the difference's truncation error is 1e-12 of the curvature, its rounding 1e-10.
void check_min_m1_gradient(const CollapsibleOptions& options) {
  CollapsibleChannelProblem problem(options);
  Vector u = perturbed_state(problem, FluidModel::OldroydB, false);
  const DofMap& d = problem.dofs();
  const bool two_modes = d.has_field("conformation_fast");
  if (two_modes) {
    // the second mode's M halved (still positive definite): the smallest m1 is in that mode
    const int fm = d.field_index("conformation_fast");
    for (int n = 0; n < problem.mesh().num_nodes(); ++n)
      for (int k = 0; k < 3; ++k)
        if (d.node_dof(fm, n, k) >= 0) u[d.node_dof(fm, n, k)] *= 0.5;
  }
  const std::vector<std::string> names = problem.observable_names();
  int index = -1;
  for (size_t k = 0; k < names.size(); ++k) {
    if (names[k] == "min_m1")
      index = static_cast<int>(k);
    else
      EXPECT_FALSE(problem.has_observable_gradient(static_cast<int>(k))) << names[k];
  }
  ASSERT_GE(index, 0);
  ASSERT_TRUE(problem.has_observable_gradient(index));
  Vector g, gm;
  ASSERT_TRUE(problem.observable_gradient(index, u, g).is_ok());
  ASSERT_TRUE(problem.monitor_gradient(0, u, gm).is_ok());
  EXPECT_EQ((g - gm).lpNorm<Eigen::Infinity>(), 0.0);
  // the gradient lives on the minimum's mode's unknowns
  const int fm = d.field_index(two_modes ? "conformation_fast" : "conformation");
  int on_mode = 0;
  for (int n = 0; n < problem.mesh().num_nodes(); ++n)
    for (int k = 0; k < 3; ++k)
      if (d.node_dof(fm, n, k) >= 0 && g[d.node_dof(fm, n, k)] != 0.0) ++on_mode;
  EXPECT_GT(on_mode, 0);
  EXPECT_EQ(on_mode, (g.array() != 0.0).count());
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-1, 1);
  Vector v(u.size());
  for (int i = 0; i < v.size(); ++i) v[i] = U(rng);
  const double h = 1e-6;
  const double fd = (problem.observable("min_m1", u + h * v) - problem.observable("min_m1", u - h * v)) / (2 * h);
  std::cout << "d min_m1 along v: gradient " << g.dot(v) << ", differences " << fd << "\n";
  EXPECT_NEAR(g.dot(v), fd, 1e-6 * std::max(1.0, std::abs(fd)));
}

TEST(CollapsibleJacobian, MinM1ObservableGradientAgainstDifferences) {
  check_min_m1_gradient(coarse_options(FluidModel::OldroydB, false));
  // two modes: min_m1's places are every mode's nodes
  check_min_m1_gradient(two_mode_options(FluidModel::OldroydB, false));
  // a Newtonian fluid has no conformation: no gradient
  CollapsibleChannelProblem newtonian(coarse_options(FluidModel::Newtonian, false));
  for (int k = 0; k < static_cast<int>(newtonian.observable_names().size()); ++k)
    EXPECT_FALSE(newtonian.has_observable_gradient(k));
}
