// The physical mass matrix of the collapsible channel (dynamics.mass_matrix = "moving-wall"), for
// each fluid on a coarse mesh: B against central differences of the time-dependent residual's time
// terms in the rates (the mesh velocity's columns first: the ALE terms), a field at rest in space
// on a moving mesh (its time terms vanish: the ALE derivative is the rate at a fixed point), the
// kinematic rows v = dx/dt of the interface, and the steady Jacobian of the moving-wall form.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <random>

#include "core/KernelTerm.hpp"
#include "core/Newton.hpp"
#include "core/RateConstraintTerm.hpp"
#include "problems/analytic/Brusselator1DProblem.hpp"
#include "problems/channel/CollapsibleChannelProblem.hpp"
#include "problems/kernels/NewtonianFlowKernel.hpp"
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
  o.fluid.constants.b = 20.0;
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

// B's columns against central differences of the time terms R(udot) = B(u) udot (time_residual):
// every column flagged in `every` and every other one of the rest; the largest error relative to
// each row's largest entry, and the largest entry of B in a flagged column of an unflagged row.
struct DifferenceCheck {
  double worst = 0.0, worst_of = 0.0, coupling = 0.0;
  int checked = 0, columns_of = 0;
};

DifferenceCheck check_against_differences(CollapsibleChannelProblem& problem, const Vector& u,
                                          const std::vector<char>& every) {
  DifferenceCheck out;
  SparseMatrix B;
  EXPECT_TRUE(problem.mass_matrix(u, B).is_ok());
  const Eigen::MatrixXd Bd = Eigen::MatrixXd(B);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-1, 1);
  Vector udot(problem.size());
  for (long i = 0; i < udot.size(); ++i) udot[i] = U(rng);
  const Eigen::VectorXd row_scale = Bd.cwiseAbs().rowwise().maxCoeff();
  Vector Rp, Rm;
  for (int j = 0; j < problem.size(); ++j) {
    const bool flagged = every[static_cast<size_t>(j)];
    if (!flagged && j % 2 != 0) continue;
    const double h = 1e-3;
    Vector up = udot, um = udot;
    up[j] += h;
    um[j] -= h;
    EXPECT_TRUE(problem.time_residual(u, up, Rp).is_ok());
    EXPECT_TRUE(problem.time_residual(u, um, Rm).is_ok());
    const Vector column = (Rp - Rm) / (2.0 * h);
    for (int i = 0; i < problem.size(); ++i) {
      if (row_scale[i] == 0.0 && column[i] == 0.0) continue;
      const double e = std::abs(column[i] - Bd(i, j)) / std::max(row_scale[i], 1e-300);
      out.worst = std::max(out.worst, e);
      if (flagged) out.worst_of = std::max(out.worst_of, e);
    }
    ++out.checked;
    if (flagged) ++out.columns_of;
  }
  for (int j = 0; j < problem.size(); ++j)
    if (every[static_cast<size_t>(j)])
      for (int i = 0; i < problem.size(); ++i)
        if (!every[static_cast<size_t>(i)]) out.coupling = std::max(out.coupling, std::abs(Bd(i, j)));
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
    const DifferenceCheck c = check_against_differences(problem, u, position_unknowns(problem));
    std::cout << f.name << ": " << problem.size() << " unknowns, " << c.checked << " columns (" << c.columns_of
              << " of positions), max relative error " << c.worst << " (positions " << c.worst_of
              << "), largest ALE entry " << c.coupling << "\n";
    EXPECT_LT(c.worst, 1e-9);
    EXPECT_GT(c.coupling, 0.0);
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

namespace {

// coarse() with the wall's inertia: rho_s / rho = ratio.
CollapsibleOptions with_wall_inertia(const Fluid& f, double ratio) {
  CollapsibleOptions o = coarse(f, true);
  o.wall_density_ratio = ratio;
  return o;
}

std::vector<char> field_unknowns(const CollapsibleChannelProblem& problem, const std::string& field) {
  const DofMap& d = problem.dofs();
  const int fi = d.field_index(field);
  std::vector<char> out(static_cast<size_t>(problem.size()), 0);
  for (int n = 0; n < problem.mesh().num_nodes(); ++n)
    for (int c = 0; c < d.num_components(fi); ++c)
      if (d.node_dof(fi, n, c) >= 0) out[static_cast<size_t>(d.node_dof(fi, n, c))] = 1;
  return out;
}

}  // namespace

// The wall's inertia: B's wall-velocity columns (rho* dw/dt in the solid's rows) and the kinematic
// rows w = dx/dt against differences of the time terms, for a Newtonian and an Oldroyd-B fluid.
TEST(MovingWallMass, WallInertiaMatchesFiniteDifferencesOfTheTimeTerms) {
  for (const Fluid& f : {kFluids[0], kFluids[1]}) {
    SCOPED_TRACE(f.name);
    CollapsibleChannelProblem problem(with_wall_inertia(f, 3.0));
    const Vector u = perturbed_state(problem, f);
    const std::vector<char> w = field_unknowns(problem, "wall_velocity");
    const DifferenceCheck c = check_against_differences(problem, u, w);
    std::cout << f.name << " with wall inertia: " << problem.size() << " unknowns, " << c.columns_of
              << " wall-velocity columns, max relative error " << c.worst << ", largest inertia entry " << c.coupling
              << "\n";
    EXPECT_LT(c.worst, 1e-9);
    EXPECT_GT(c.coupling, 0.0);  // rho* dw/dt is in the solid's rows
    // the kinematic rows: R = -dx/dt for w = dx/dt, one per wall-velocity unknown
    int kinematic = 0;
    for (const auto& t : problem.assembler().terms())
      if (t->name() == "wall kinematics") kinematic += t->num_items();
    EXPECT_EQ(kinematic, static_cast<int>(std::count(w.begin(), w.end(), 1)));
  }
}

// rho* is the density ratio times the fluid's inertia coefficient Re / Gamma: the consistent mass
// matrices of the solid's elements sum to rho* times the wall's reference area L t (the Q2 shape
// functions sum to one; the 3x3 Gauss rule is exact on the affine reference shapes), at two
// thicknesses (the reference shape follows t).
TEST(MovingWallMass, WallInertiaIsTheDensityRatioTimesReOverGammaOverTheArea) {
  const double ratio = 2.5;
  for (double t : {0.4, 0.15}) {
    CollapsibleOptions o = with_wall_inertia(kFluids[0], ratio);
    o.geometry.thickness = t;
    CollapsibleChannelProblem problem(o);
    const double expected = ratio * o.fluid.Re / o.Gamma * 5.0 * t;
    double total = 0.0;
    int terms = 0;
    for (const auto& term : problem.assembler().terms()) {
      if (term->name() != "solid-inertia") continue;
      ++terms;
      std::vector<double> B(static_cast<size_t>(term->local_rows() * term->local_size()));
      for (int item = 0; item < term->num_items(); ++item) {
        ASSERT_TRUE(term->mass(item, nullptr, B.data()).is_ok());
        for (int a = 0; a < 9; ++a)
          for (int b = 0; b < 9; ++b) total += B[static_cast<size_t>(a * term->local_size() + 18 + b)];
      }
    }
    ASSERT_EQ(terms, 1);
    EXPECT_NEAR(total, expected, 1e-12 * expected) << "t = " << t;
  }
}

// The steady problem does not see the wall's inertia: the same steady state (w = 0) and observables
// as without it, to Newton's tolerance.
TEST(MovingWallMass, WallInertiaLeavesTheSteadyStateUnchanged) {
  // (the Dynamics tests' channel: Newtonian, Re = 1, Gamma = 4.95e-4, Pe = 0.04)
  CollapsibleOptions o;
  o.mesh = test::custom_channel_mesh(5, 10, 5, 4, 2);
  o.Gamma = 4.95e-4;
  o.Pe = 0.04;
  o.fluid.model = FluidModel::Newtonian;
  o.fluid.Re = 1.0;
  o.fluid.inertia = true;
  o.moving_wall_dynamics = true;
  CollapsibleChannelProblem plain(o);
  o.wall_density_ratio = 10.0;
  CollapsibleChannelProblem heavy(o);
  Vector up = plain.initial_guess(), uh = heavy.initial_guess();
  ASSERT_TRUE(NewtonSolver(plain).solve(up).converged());
  ASSERT_TRUE(NewtonSolver(heavy).solve(uh).converged());
  std::vector<double> op, oh;
  ASSERT_TRUE(plain.observables(up, op).is_ok());
  ASSERT_TRUE(heavy.observables(uh, oh).is_ok());
  ASSERT_EQ(op.size(), oh.size());
  for (size_t k = 0; k < op.size(); ++k) EXPECT_NEAR(oh[k], op[k], 1e-9 * std::max(1.0, std::abs(op[k]))) << k;
  const std::vector<char> w = field_unknowns(heavy, "wall_velocity");
  for (int i = 0; i < heavy.size(); ++i)
    if (w[static_cast<size_t>(i)]) {
      EXPECT_EQ(uh[i], 0.0);
    }
}

// A density ratio without the moving-wall form, or without fluid inertia, is refused naming the key.
TEST(MovingWallMass, WallInertiaNeedsTheMovingWallFormAndFluidInertia) {
  CollapsibleOptions fixed = with_wall_inertia(kFluids[0], 1.0);
  fixed.moving_wall_dynamics = false;
  CollapsibleOptions stokes = with_wall_inertia(kFluids[0], 1.0);
  stokes.fluid.Re = 0.0;
  stokes.fluid.inertia = false;
  for (const CollapsibleOptions& o : {fixed, stokes}) {
    try {
      CollapsibleChannelProblem problem(o);
      ADD_FAILURE() << "built";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("dynamics.wall_density_ratio"), std::string::npos) << e.what();
    }
  }
}

// The time-dependent residual G = F(u) + B(u) udot that time steps and the shooting map's products
// evaluate (time_dependent_residual, core/Problem.hpp) in one pass over the terms: the Newtonian
// moving-mesh kernel shares the element's geometry between its residual and its rate
// (evaluate_with_rate), the other kernels and the wall's inertia term take the default (the two
// calls). Against residual + time_residual, which differ only in the order of the sums: rounding,
// 1e-13 of the largest of F and B udot. A plain Problem (the Brusselator) takes the same two
// calls exactly.
TEST(MovingWallMass, TheTimeDependentResidualIsTheResidualPlusTheTimeTermsInOnePass) {
  static_assert(KernelTerm<NewtonianFlowKernel<true>>::kHasFused, "the Newtonian kernel evaluates both at once");
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-1, 1);
  for (const Fluid& f : kFluids) {
    for (int variant = 0; variant < 3; ++variant) {  // a fixed wall, a moving one, a moving one with inertia
      SCOPED_TRACE(std::string(f.name) + " variant " + std::to_string(variant));
      CollapsibleChannelProblem problem(variant == 2 ? with_wall_inertia(f, 3.0) : coarse(f, variant == 1));
      const Vector u = perturbed_state(problem, f);
      Vector udot(problem.size());
      for (long i = 0; i < udot.size(); ++i) udot[i] = U(rng);
      Vector F, R, G;
      ASSERT_TRUE(problem.residual(u, F).is_ok());
      ASSERT_TRUE(problem.time_residual(u, udot, R).is_ok());
      ASSERT_TRUE(time_dependent_residual(problem, u, udot, G).is_ok());
      const double scale = std::max(F.lpNorm<Eigen::Infinity>(), R.lpNorm<Eigen::Infinity>());
      EXPECT_GT(R.lpNorm<Eigen::Infinity>(), 1e-3 * scale);  // the time terms are not negligible
      EXPECT_LE((G - (F + R)).lpNorm<Eigen::Infinity>(), 1e-13 * scale);
    }
  }
  Brusselator1DOptions options;
  options.intervals = 8;
  Brusselator1DProblem brusselator(options);
  const Vector u = brusselator.initial_guess() + 0.1 * Vector::Ones(brusselator.size());
  const Vector udot = Vector::LinSpaced(brusselator.size(), -1.0, 2.0);
  Vector F, R, G;
  ASSERT_TRUE(time_dependent_residual(brusselator, u, udot, G).is_ok());
  ASSERT_TRUE(brusselator.residual(u, F).is_ok());
  ASSERT_TRUE(brusselator.time_residual(u, udot, R).is_ok());
  EXPECT_EQ((G - (F + R)).lpNorm<Eigen::Infinity>(), 0.0);
}

// An inverted fluid element fails the fused evaluation as it fails the residual: a status naming
// the element, not a value.
TEST(MovingWallMass, TheTimeDependentResidualOfAnInvertedElementIsAStatus) {
  CollapsibleChannelProblem problem(coarse(kFluids[0], true));
  Vector u = problem.initial_guess();
  const DofMap& d = problem.dofs();
  const int fx = d.field_index("position");
  const auto& element = problem.mesh().element(0);  // upstream: a fluid element
  // the element's centre node pushed past its corner: det J < 0 at Gauss points
  const int centre = d.node_dof(fx, element[4], 0), corner = d.node_dof(fx, element[8], 0);
  u[centre] = u[corner] + 1.0;
  Vector F, G;
  const Status expected = problem.residual(u, F);
  ASSERT_FALSE(expected.is_ok());
  const Status st = time_dependent_residual(problem, u, Vector::Zero(problem.size()), G);
  EXPECT_EQ(st.code(), expected.code());
  EXPECT_EQ(st.message(), expected.message());
  EXPECT_NE(st.message().find("inverted"), std::string::npos) << st.message();
}
