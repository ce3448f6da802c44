// Every element kernel's AD Jacobian and every dF/dp against central finite differences, on
// distorted (curved, non-parallelogram) elements. Fails above a relative error of 1e-6; the
// central-difference truncation and rounding error at h = 1e-6 is about 1e-9 here.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <random>

#include "problems/analytic/Bratu2DProblem.hpp"
#include "problems/channel/ChannelProblem.hpp"
#include "support/TestSupport.hpp"

using namespace keller;

namespace {

// Moves every node (curving the edges) by up to `amplitude` of the element size; the inflow's and
// outflow's nodes slide along them (fully developed flow there needs lines x = const).
void distort_all_nodes(Mesh& m, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1, 1);
  std::vector<int> ends = m.boundary_nodes("inflow"), outflow = m.boundary_nodes("outflow");
  ends.insert(ends.end(), outflow.begin(), outflow.end());
  std::sort(ends.begin(), ends.end());
  for (int n = 0; n < m.num_nodes(); ++n) {
    auto p = m.node(n);
    const double dx = amplitude * U(rng);
    if (!std::binary_search(ends.begin(), ends.end(), n)) p[0] += dx;
    p[1] += amplitude * U(rng);
    m.set_node(n, p);
  }
}

ChannelOptions small_channel(double Re) {
  ChannelOptions o;
  o.mesh.name = "custom";
  o.mesh.nx_upstream = 2;
  o.mesh.nx_deformable = 3;
  o.mesh.nx_downstream = 2;
  o.mesh.ny_fluid = 2;
  o.fluid.Re = Re;
  o.Gamma = 0.7;
  o.fluid.inertia = Re > 0;
  return o;
}

Vector random_state(int n, unsigned seed, double scale) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1, 1);
  Vector u(n);
  for (int i = 0; i < n; ++i) u[i] = scale * U(rng);
  return u;
}

}  // namespace

TEST(KernelJacobian, NewtonianFlowOnDistortedElements) {
  for (double Re : {0.0, 10.0}) {
    const ChannelOptions o = small_channel(Re);
    Mesh mesh = build_channel_mesh(o.geometry, o.mesh, false);
    distort_all_nodes(mesh, 0.08, 7);  // elements are >= 0.5 wide: curved but valid
    ASSERT_GT(mesh.jacobian_range().first, 0.0);
    ChannelProblem problem(o, mesh);
    const Term& kernel = *problem.assembler().terms()[0];
    ASSERT_EQ(kernel.name(), "newtonian-flow");
    double worst = 0;
    for (int item = 0; item < kernel.num_items(); ++item) {
      const Vector u = random_state(kernel.local_size(), 100 + item, 1.0);
      const auto c = test::check_term_jacobian(kernel, item, std::vector<double>(u.data(), u.data() + u.size()));
      worst = std::max(worst, c.max_relative_error);
    }
    std::cout << "newtonian-flow kernel (Re = " << Re << "): max relative error " << worst << "\n";
    RecordProperty("max_relative_error_Re" + std::to_string(int(Re)), std::to_string(worst));
    EXPECT_LT(worst, 1e-6);
  }
}

TEST(KernelJacobian, WholeChannelProblemAndParameterDerivatives) {
  const ChannelOptions o = small_channel(10.0);
  Mesh mesh = build_channel_mesh(o.geometry, o.mesh, false);
  distort_all_nodes(mesh, 0.05, 3);
  ChannelProblem problem(o, mesh);
  const Vector u = random_state(problem.size(), 11, 1.0);
  const auto c = test::check_problem_jacobian(problem, u);
  std::cout << "channel problem Jacobian: max relative error " << c.max_relative_error << " at (" << c.worst_row << ", "
            << c.worst_col << ")\n";
  EXPECT_LT(c.max_relative_error, 1e-6);
  for (const char* p : {"Re", "Gamma"}) {
    const double e = test::check_parameter_derivative(problem, problem.parameters().index(p), u);
    std::cout << "dF/d" << p << ": max relative error " << e << "\n";
    EXPECT_LT(e, 1e-6) << p;
  }
  // dF/dGamma is not zero (inflow values and the inertia coefficient Re/Gamma depend on it)
  Vector dF;
  problem.parameter_derivative(problem.parameters().index("Gamma"), u, dF);
  EXPECT_GT(dF.cwiseAbs().maxCoeff(), 1e-3);
}

TEST(KernelJacobian, Bratu2D) {
  Bratu2DProblem problem(3, 2.5);
  const Vector u = random_state(problem.size(), 5, 0.5);
  const auto c = test::check_problem_jacobian(problem, u);
  std::cout << "bratu2d Jacobian: max relative error " << c.max_relative_error << "\n";
  EXPECT_LT(c.max_relative_error, 1e-6);
  const double e = test::check_parameter_derivative(problem, 0, u);
  std::cout << "bratu2d dF/dlambda: max relative error " << e << "\n";
  EXPECT_LT(e, 1e-6);
}

// Mass matrices against exact integrals of Q2 basis functions on an hx x hy rectangle: the
// centre node's function integrates to (2/3)^2 hx hy, a vertex node's to (1/6)^2 hx hy per
// element. Row sums of B are these integrals (times Re/Gamma for velocity rows); Dirichlet and
// continuity rows carry no time derivative.
TEST(MassMatrix, RowSumsAreBasisIntegrals) {
  ChannelOptions o = small_channel(4.0);
  ChannelProblem channel(o);
  SparseMatrix B;
  ASSERT_TRUE(channel.mass_matrix(channel.initial_guess(), B).is_ok());
  const Vector rows = B * Vector::Ones(channel.size());
  const double rho = o.fluid.Re / o.Gamma;
  const int fv = channel.dofs().field_index("velocity"), fp = channel.dofs().field_index("pressure");
  const Mesh& m = channel.mesh();
  for (int e = 0; e < m.num_elements(); ++e) {
    const auto& el = m.element(e);
    const double hx = m.node(el[2])[0] - m.node(el[0])[0], hy = m.node(el[6])[1] - m.node(el[0])[1];
    for (int c = 0; c < 2; ++c)
      EXPECT_NEAR(rows[channel.dofs().node_dof(fv, el[4], c)], rho * 4.0 / 9.0 * hx * hy, 1e-12);
    EXPECT_EQ(rows[channel.dofs().element_dof(fp, e, 0, 0)], 0.0);
  }
  for (int i = 0; i < channel.size(); ++i)
    if (channel.assembler().row_owned(i)) {
      EXPECT_EQ(rows[i], 0.0);
    }

  Bratu2DProblem bratu(4, 1.0);
  ASSERT_TRUE(bratu.mass_matrix(bratu.initial_guess(), B).is_ok());
  const Vector brows = B * Vector::Ones(bratu.size());
  const double h = 0.25;
  for (int n = 0; n < bratu.mesh().num_nodes(); ++n) {
    const auto& p = bratu.mesh().node(n);
    const double b = brows[bratu.dofs().node_dof(0, n, 0)];
    if (std::abs(p[0] - 0.5) < 1e-12 && std::abs(p[1] - 0.5) < 1e-12) {  // interior vertex, 4 elements
      EXPECT_NEAR(b, 4 * h * h / 36.0, 1e-15);
    }
    if (std::abs(p[0] - 0.125) < 1e-12 && std::abs(p[1] - 0.625) < 1e-12) {  // an element centre
      EXPECT_NEAR(b, 4 * h * h / 9.0, 1e-15);
    }
    if (p[0] < 1e-12) {
      EXPECT_EQ(b, 0.0);  // Dirichlet row
    }
  }
}

// A multi-mode fluid's time terms: every mode's conformation rows carry the same SUPG-weighted
// Q1 mass (PolymerModeKernel::rate and the first mode's kernel weight dM_k/dt alike), so at the
// same state the row sums of B over the second mode's unknowns are the first mode's, node by
// node and component by component (to rounding), and not zero away from the inflow.
TEST(MassMatrix, EveryModeHasTheFirstModesTimeTerms) {
  ChannelOptions o = small_channel(4.0);
  o.fluid.model = FluidModel::OldroydB;
  o.fluid.Wi = 0.3;
  o.fluid.modes = {{"a", 1.0, 0.5}, {"b", 0.2, 0.5}};
  ChannelProblem channel(o);
  SparseMatrix B;
  ASSERT_TRUE(channel.mass_matrix(channel.initial_guess(), B).is_ok());
  const Vector rows = B * Vector::Ones(channel.size());
  const DofMap& d = channel.dofs();
  const int f1 = d.field_index("conformation"), f2 = d.field_index("conformation_b");
  int compared = 0;
  for (int n = 0; n < channel.mesh().num_nodes(); ++n)
    for (int c = 0; c < 3; ++c) {
      const int i = d.node_dof(f1, n, c), j = d.node_dof(f2, n, c);
      if (i < 0) continue;
      ASSERT_GE(j, 0);
      EXPECT_NEAR(rows[j], rows[i], 1e-14 * std::abs(rows[i]) + 1e-16);
      if (rows[i] != 0.0) ++compared;
    }
  EXPECT_GT(compared, 0);
}
