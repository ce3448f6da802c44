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

void check(FluidModel model, bool log_form) {
  SCOPED_TRACE(std::string(to_string(model)) + (log_form ? " log" : ""));
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
  o.fluid.b = 20.0;
  o.fluid.Re = 0.01;  // inertia on, so dF/dRe is checked too (and Re = 0 sits on its bound)
  o.fluid.inertia = true;
  o.fluid.profile = model == FluidModel::Newtonian ? ProfileKind::Parabolic : ProfileKind::FullyDeveloped;
  CollapsibleChannelProblem problem(o);
  Vector u = problem.initial_guess();
  const DofMap& d = problem.dofs();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1, 1);
  const int fx = d.field_index("position");
  for (int n = 0; n < problem.mesh().num_nodes(); ++n)
    for (int c = 0; c < 2; ++c) u[d.node_dof(fx, n, c)] += 0.03 * U(rng);
  for (int f = 0; f < d.num_fields(); ++f) {
    if (d.field(f).name == "position" || d.field(f).name == "conformation") continue;
    for (int n = 0; n < problem.mesh().num_nodes(); ++n)
      for (int c = 0; c < d.num_components(f); ++c)
        if (d.node_dof(f, n, c) >= 0) u[d.node_dof(f, n, c)] += 0.05 * U(rng);
  }
  if (model != FluidModel::Newtonian) {
    const int fm = d.field_index("conformation");
    for (int n = 0; n < problem.mesh().num_nodes(); ++n)
      for (int k = 0; k < d.num_components(fm); ++k)
        if (d.node_dof(fm, n, k) >= 0)
          u[d.node_dof(fm, n, k)] = log_form ? 0.4 * U(rng) : (k == 1 ? 0.3 * U(rng) : 1.2 + 0.4 * U(rng));
  }
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
