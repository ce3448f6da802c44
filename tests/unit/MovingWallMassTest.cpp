// The physical mass matrix of the collapsible channel (dynamics.mass_matrix = "moving-wall"), for
// each fluid on a coarse mesh: B against central differences of the time-dependent residual's time
// terms in the rates (the mesh velocity's columns first: the ALE terms), a field at rest in space
// on a moving mesh (its time terms vanish: the ALE derivative is the rate at a fixed point), the
// kinematic rows v = dx/dt of the interface, and the steady Jacobian of the moving-wall form.
#include <gtest/gtest.h>

#include <iostream>
#include <random>

#include "core/RateConstraintTerm.hpp"
#include "problems/channel/CollapsibleChannelProblem.hpp"
#include "support/TestSupport.hpp"

using namespace keller;

namespace {

struct Fluid {
  FluidModel model;
  bool log_form;
  bool dynamic_zz;
  const char* name;
};

const Fluid kFluids[] = {{FluidModel::Newtonian, false, false, "newtonian"},
                         {FluidModel::OldroydB, false, false, "oldroyd-b"},
                         {FluidModel::OldroydB, true, false, "oldroyd-b log"},
                         {FluidModel::FeneP, false, true, "fene-p (dynamic M_zz)"},
                         {FluidModel::Owens, false, false, "owens"}};

CollapsibleOptions coarse(const Fluid& f, bool moving_wall) {
  CollapsibleOptions o;
  o.mesh = test::custom_channel_mesh(1, 3, 1, 2, 1);  // CollapsibleJacobianTest's mesh
  o.Gamma = 0.05;
  o.Pe = 0.3;
  o.fluid.model = f.model;
  o.fluid.log_conformation = f.log_form;
  o.fluid.dynamic_zz = f.dynamic_zz;
  o.fluid.Wi = 0.7;
  o.fluid.beta = 0.3;
  o.fluid.b = 20.0;
  o.fluid.Re = 0.5;  // fluid inertia on: the velocity rows carry time terms
  o.fluid.inertia = true;
  o.moving_wall_dynamics = moving_wall;
  return o;
}

// A perturbed state (as in CollapsibleJacobianTest): moved nodes, flow fields off their values.
Vector perturbed_state(CollapsibleChannelProblem& problem, const Fluid& f) {
  Vector u = problem.initial_guess();
  const DofMap& d = problem.dofs();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int fi = 0; fi < d.num_fields(); ++fi)
    for (int n = 0; n < problem.mesh().num_nodes(); ++n)
      for (int c = 0; c < d.num_components(fi); ++c) {
        const int dof = d.node_dof(fi, n, c);
        if (dof < 0) continue;
        const std::string& name = d.field(fi).name;
        if (name == "position")
          u[dof] += 0.03 * U(rng);
        else if (name == "conformation")
          u[dof] = f.log_form ? 0.4 * U(rng) : (c == 1 ? 0.3 * U(rng) : 1.2 + 0.4 * U(rng));
        else
          u[dof] += 0.05 * U(rng);
      }
  return u;
}

// Which unknowns are node positions.
std::vector<char> position_unknowns(const CollapsibleChannelProblem& problem) {
  const DofMap& d = problem.dofs();
  const int fx = d.field_index("position");
  std::vector<char> out(static_cast<size_t>(problem.size()), 0);
  for (int n = 0; n < problem.mesh().num_nodes(); ++n)
    for (int c = 0; c < 2; ++c)
      if (d.node_dof(fx, n, c) >= 0) out[static_cast<size_t>(d.node_dof(fx, n, c))] = 1;
  return out;
}

}  // namespace

// B's columns against central differences of R(udot) = B(u) udot, the time terms assembled from the
// kernels' rates in double precision (a separate evaluation from B, which dual numbers take from
// the same rates), redirects of the interface rows included. R is linear in udot, so the
// differences are exact to rounding: 1e-9 relative to the largest entry of each row leaves room
// for it. Every column of the node positions (the mesh velocity) is checked, and every other one.
TEST(MovingWallMass, MatchesFiniteDifferencesOfTheTimeTerms) {
  for (const Fluid& f : kFluids) {
    SCOPED_TRACE(f.name);
    CollapsibleChannelProblem problem(coarse(f, true));
    const Vector u = perturbed_state(problem, f);
    SparseMatrix B;
    ASSERT_TRUE(problem.mass_matrix(u, B).is_ok());
    const Eigen::MatrixXd Bd = Eigen::MatrixXd(B);
    const std::vector<char> is_position = position_unknowns(problem);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> U(-1, 1);
    Vector udot(problem.size());
    for (long i = 0; i < udot.size(); ++i) udot[i] = U(rng);
    Eigen::VectorXd row_scale = Bd.cwiseAbs().rowwise().maxCoeff();
    double worst = 0.0, worst_position = 0.0;
    int checked = 0, position_columns = 0;
    Vector Rp, Rm;
    for (int j = 0; j < problem.size(); ++j) {
      const bool position = is_position[static_cast<size_t>(j)];
      if (!position && j % 2 != 0) continue;
      const double h = 1e-3;
      Vector up = udot, um = udot;
      up[j] += h;
      um[j] -= h;
      ASSERT_TRUE(problem.time_residual(u, up, Rp).is_ok());
      ASSERT_TRUE(problem.time_residual(u, um, Rm).is_ok());
      const Vector column = (Rp - Rm) / (2.0 * h);
      for (int i = 0; i < problem.size(); ++i) {
        const double e = std::abs(column[i] - Bd(i, j)) / std::max(row_scale[i], 1e-300);
        if (row_scale[i] == 0.0 && column[i] == 0.0) continue;
        worst = std::max(worst, e);
        if (position) worst_position = std::max(worst_position, e);
      }
      ++checked;
      if (position) ++position_columns;
    }
    // the ALE terms are there: B has entries in the position columns of flow rows
    double ale = 0.0;
    for (int j = 0; j < problem.size(); ++j)
      if (is_position[static_cast<size_t>(j)])
        for (int i = 0; i < problem.size(); ++i)
          if (!is_position[static_cast<size_t>(i)]) ale = std::max(ale, std::abs(Bd(i, j)));
    std::cout << f.name << ": " << problem.size() << " unknowns, " << checked << " columns (" << position_columns
              << " of positions), max relative error " << worst << " (positions " << worst_position
              << "), largest ALE entry " << ale << "\n";
    EXPECT_LT(worst, 1e-9);
    EXPECT_GT(ale, 0.0);
  }
}

// A velocity and a conformation linear in x and y on a mesh of parallelograms (Q2 and Q1 hold them
// exactly), the mesh moving at an affine velocity xdot: the fields at rest in space have nodal
// rates xdot . grad (each node moves to where the field differs), and the rate at a fixed point,
// B udot, is zero in every flow row and in the solid rows that receive the interface's reaction;
// the kinematic rows read -xdot (B du/dt = -F with F = v). The former B (fixed-wall: the nodal
// rates alone) misses the ALE term and does not vanish: the test can tell.
TEST(MovingWallMass, AFieldAtRestOnAMovingMeshHasNoTimeTerms) {
  for (const Fluid& f : kFluids) {
    SCOPED_TRACE(f.name);
    for (bool moving_wall : {true, false}) {
      CollapsibleChannelProblem problem(coarse(f, moving_wall));
      const DofMap& d = problem.dofs();
      const Mesh& mesh = problem.mesh();
      Vector u = problem.initial_guess(), udot = Vector::Zero(problem.size());
      const int fx = d.field_index("position"), fv = d.field_index("velocity");
      const int fm = f.model == FluidModel::Newtonian ? -1 : d.field_index("conformation");
      // every element a parallelogram: mid-side and centre nodes where the vertices put them (the
      // generated rectangles, graded, have them elsewhere)
      for (int e = 0; e < mesh.num_elements(); ++e) {
        const auto& el = mesh.element(e);
        auto at = [&](int a, int c) { return u[d.node_dof(fx, el[a], c)]; };
        for (int c = 0; c < 2; ++c) {
          const double v0 = at(0, c), v2 = at(2, c), v6 = at(6, c), v8 = at(8, c);
          const double mid[9] = {v0, 0.5 * (v0 + v2), v2, 0.5 * (v0 + v6), 0.25 * (v0 + v2 + v6 + v8), 0.5 * (v2 + v8),
                                 v6, 0.5 * (v6 + v8), v8};
          for (int a = 0; a < 9; ++a) u[d.node_dof(fx, el[a], c)] = mid[a];
        }
      }
      // the fields (arbitrary affine coefficients) and the affine mesh velocity
      const double K[2][2] = {{0.3, -0.7}, {0.2, 0.5}}, v0[2] = {0.1, -0.05};
      const double G[4][2] = {{0.4, -0.2}, {0.1, 0.3}, {-0.25, 0.15}, {0.05, 0.2}}, m0[4] = {1.3, 0.2, 0.9, 1.1};
      auto xdot = [](double x, double y, int c) {
        return c == 0 ? 0.2 + 0.03 * x - 0.4 * y : -0.1 + 0.05 * x + 0.1 * y;
      };
      for (int n = 0; n < mesh.num_nodes(); ++n) {
        if (d.node_dof(fx, n, 0) < 0) continue;
        const double x = u[d.node_dof(fx, n, 0)], y = u[d.node_dof(fx, n, 1)];
        const double w[2] = {xdot(x, y, 0), xdot(x, y, 1)};
        for (int c = 0; c < 2; ++c) udot[d.node_dof(fx, n, c)] = w[c];
        for (int c = 0; c < 2; ++c) {
          const int dv = d.node_dof(fv, n, c);
          if (dv < 0) continue;
          u[dv] = v0[c] + K[c][0] * x + K[c][1] * y;
          udot[dv] = K[c][0] * w[0] + K[c][1] * w[1];
        }
        for (int c = 0; fm >= 0 && c < d.num_components(fm); ++c) {
          const int dm = d.node_dof(fm, n, c);
          if (dm < 0) continue;
          u[dm] = m0[c] + G[c][0] * x + G[c][1] * y;
          udot[dm] = G[c][0] * w[0] + G[c][1] * w[1];
        }
      }
      Vector R;
      ASSERT_TRUE(problem.time_residual(u, udot, R).is_ok());
      SparseMatrix B;
      ASSERT_TRUE(problem.mass_matrix(u, B).is_ok());
      // the size of the terms each row sums: |B| |udot|
      const Vector scale = B.cwiseAbs() * udot.cwiseAbs();
      const Assembler& assembler = problem.assembler();
      double worst = 0.0, kinematic = 0.0;
      int kinematic_rows = 0;
      // the kinematic rows: where the interface velocity is tied to its node's rate
      std::vector<char> is_kinematic(static_cast<size_t>(problem.size()), 0);
      for (const auto& t : assembler.terms())
        if (const auto* k = dynamic_cast<const RateConstraintTerm*>(t.get()))
          for (const auto& [row, of] : k->pairs()) {
            is_kinematic[static_cast<size_t>(row)] = 1;
            kinematic = std::max(kinematic, std::abs(R[row] + udot[of]));
            ++kinematic_rows;
          }
      for (int i = 0; i < problem.size(); ++i)
        if (!is_kinematic[static_cast<size_t>(i)] && scale[i] > 0.0) worst = std::max(worst, std::abs(R[i]) / scale[i]);
      std::cout << f.name << (moving_wall ? " moving-wall" : " fixed-wall") << ": max |B udot| / (|B| |udot|) " << worst
                << " over the flow and solid rows, kinematic rows " << kinematic_rows << " off by " << kinematic
                << "\n";
      if (moving_wall) {
        EXPECT_LT(worst, 1e-12);
        EXPECT_GT(kinematic_rows, 0);
        EXPECT_LT(kinematic, 1e-15);
      } else {
        EXPECT_GT(worst, 1e-2);  // the nodal rates alone: a field at rest seems to change
        EXPECT_EQ(kinematic_rows, 0);
      }
    }
  }
}

// The steady Jacobian of the moving-wall form (the kinematic rows' structure in the pattern) against
// central differences, as CollapsibleJacobianTest checks the fixed-wall form; its residual is the
// same at every state.
TEST(MovingWallMass, TheSteadyProblemIsUnchanged) {
  for (const Fluid& f : kFluids) {
    SCOPED_TRACE(f.name);
    CollapsibleChannelProblem moving(coarse(f, true)), fixed(coarse(f, false));
    const Vector u = perturbed_state(moving, f);
    Vector Fm, Ff;
    ASSERT_TRUE(moving.residual(u, Fm).is_ok());
    ASSERT_TRUE(fixed.residual(u, Ff).is_ok());
    EXPECT_EQ((Fm - Ff).lpNorm<Eigen::Infinity>(), 0.0);
    const auto jc = test::check_problem_jacobian(moving, u);
    EXPECT_LT(jc.max_relative_error, 1e-6);
  }
}
