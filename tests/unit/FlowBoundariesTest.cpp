// Boundary conditions of FlowEquations on any named boundary, against exact solutions: Q2 holds
// the Poiseuille parabola and the Couette line exactly and P1disc the linear pressure, so these
// come out to rounding (1e-11 on unit-sized values) in any orientation; Oldroyd-B channel flow is
// not exact on the mesh, but the discrete problem is rotation covariant, so the rotated solution
// is the rotation of the unrotated one to rounding. (The refusals: FlowBoundaryRefusalTest.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

#include "core/AssembledProblem.hpp"
#include "core/BlockMeshBuilder.hpp"
#include "core/Newton.hpp"
#include "core/ReferenceElement.hpp"
#include "problems/components/Composition.hpp"
#include "problems/components/FlowEquations.hpp"
#include "support/FlowChannelMeshes.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
using namespace keller::test;

namespace {

// Steady flow of FlowEquations alone on a mesh, velocity scale 1.
class FlowOnMesh final : public AssembledProblem {
 public:
  FlowOnMesh(Mesh mesh, const FluidOptions& fluid, const FlowBoundaries& bc) : mesh_(std::move(mesh)) {
    flow_ = std::make_unique<FlowEquations>(mesh_, "fluid", fluid, bc, params_, -1);
    ComposedSystem system = Composition().add(*flow_).build(mesh_, params_);
    dofs_ = std::move(system.dofs);
    dirichlet_ = system.dirichlet;
    assemble(dofs_->size(), system.terms());
  }
  std::string name() const override { return "flow-on-mesh"; }
  Vector initial_guess() override { return with_dirichlet(false); }
  Vector with_dirichlet(bool profile) {
    Vector u = Vector::Zero(size());
    if (profile)
      flow_->initial_guess(u);
    else
      flow_->rest_state(u);
    for (int k = 0; k < dirichlet_->num_items(); ++k) u[dirichlet_->dofs()[k]] = dirichlet_->value(k);
    return u;
  }
  Vector stokes() {
    Vector u = Vector::Zero(size());
    EXPECT_TRUE(flow_->stokes_state(u).is_ok());
    return u;
  }
  Vector solve(bool profile = false) {
    Vector u = with_dirichlet(profile);
    NewtonSolver newton(*this);
    const NewtonResult r = newton.solve(u);
    EXPECT_TRUE(r.converged()) << r.status.message();
    return u;
  }
  double value(const Vector& u, const char* field, int node, int c) const {
    return u[dofs_->node_dof(dofs_->field_index(field), node, c)];
  }
  // p coefficients of element e: the value at its centre node, dp/dx, dp/dy
  std::array<double, 3> pressure(const Vector& u, int e) const {
    const int fp = dofs_->field_index("pressure");
    return {u[dofs_->element_dof(fp, e, 0, 0)], u[dofs_->element_dof(fp, e, 1, 0)], u[dofs_->element_dof(fp, e, 2, 0)]};
  }
  // int v . n ds over a boundary (n outward)
  double flow_rate(const Vector& u, const std::string& boundary) const {
    const ref::Tables& tb = ref::tables();
    double q = 0;
    for (const BoundaryEdge& be : mesh_.boundary(boundary)) {
      double xy[9][2];
      mesh_.element_nodes(be.element, xy);
      std::array<EdgeQpGeometry<double>, ref::kEdgeQp> g;
      map_edge(xy, be.edge, g);
      const auto& el = mesh_.element(be.element);
      for (int k = 0; k < ref::kEdgeQp; ++k)
        for (int a = 0; a < 9; ++a)
          q += tb.edge_N2[be.edge][k][a] * g[k].wds *
               (value(u, "velocity", el[a], 0) * g[k].normal[0] + value(u, "velocity", el[a], 1) * g[k].normal[1]);
    }
    return q;
  }
  const Mesh& mesh() const { return mesh_; }
  const Term& term(const std::string& name) const {
    for (const auto& t : assembler().terms())
      if (t->name() == name) return *t;
    throw std::invalid_argument("no term " + name);
  }

 private:
  Mesh mesh_;
  std::unique_ptr<FlowEquations> flow_;
  std::unique_ptr<DofMap> dofs_;
  std::shared_ptr<DirichletTerm> dirichlet_;
};

// Newtonian Poiseuille flow of mean velocity 1 in the channel [lo, hi] across y' = x . e2, flowing
// along e1 = map's x' direction, with P = G (x'_0 - x'), G = 12 / (hi - lo)^2: max errors.
struct PoiseuilleError {
  double velocity = 0, pressure_gradient = 0, pressure = 0;
};
PoiseuilleError poiseuille_error(const FlowOnMesh& p, const Vector& u, double degrees, double lo, double hi,
                                 double x0) {
  const double a = degrees * std::numbers::pi / 180;
  const double c = degrees == 90 ? 0.0 : degrees == 180 ? -1.0 : std::cos(a);
  const double s = degrees == 90 ? 1.0 : degrees == 180 ? 0.0 : std::sin(a);
  const double H = 0.5 * (hi - lo), G = 3.0 / (H * H);
  PoiseuilleError e;
  for (int n = 0; n < p.mesh().num_nodes(); ++n) {
    const auto& x = p.mesh().node(n);
    const double yl = -s * x[0] + c * x[1], xi = (yl - 0.5 * (lo + hi)) / H, w = 1.5 * (1 - xi * xi);
    e.velocity = std::max(
        {e.velocity, std::abs(p.value(u, "velocity", n, 0) - w * c), std::abs(p.value(u, "velocity", n, 1) - w * s)});
  }
  for (int el = 0; el < p.mesh().num_elements(); ++el) {
    const auto P = p.pressure(u, el);
    const auto& xc = p.mesh().node(p.mesh().element(el)[4]);
    const double xl = c * xc[0] + s * xc[1];
    e.pressure = std::max(e.pressure, std::abs(P[0] - G * (x0 - xl)));
    e.pressure_gradient = std::max({e.pressure_gradient, std::abs(P[1] + G * c), std::abs(P[2] + G * s)});
  }
  std::cout << "Poiseuille at " << degrees << " degrees: max errors velocity " << e.velocity << ", pressure "
            << e.pressure << ", pressure gradient " << e.pressure_gradient << "\n";
  return e;
}

}  // namespace

// A channel rotated by 30 degrees: a fully developed inflow (its frame from the segment) and the
// same profile leaving at the other end; no natural condition, so the pressure is 0 at the centre
// of the first element, P = G (x'_c - x').
TEST(FlowBoundaries, PoiseuilleInARotatedChannel) {
  const double L = 3, H = 1;
  FlowBoundaries bc;
  bc.inflows = {{"inflow"}, {"outflow", true, {0, 0}, -1.0}};
  bc.walls = {"bottom", "top"};
  FlowOnMesh p(channel(L, H, 6, 3, rotation(30)), FluidOptions{}, bc);
  const Vector u = p.solve();
  const double a = std::numbers::pi / 6;
  const auto& xc = p.mesh().node(p.mesh().element(0)[4]);
  const PoiseuilleError e = poiseuille_error(p, u, 30, 0, H, std::cos(a) * xc[0] + std::sin(a) * xc[1]);
  EXPECT_LT(e.velocity, 1e-11);
  EXPECT_LT(e.pressure_gradient, 1e-10);
  EXPECT_LT(e.pressure, 1e-10);
  EXPECT_NEAR(p.flow_rate(u, "inflow"), -H, 1e-13);
  EXPECT_NEAR(p.flow_rate(u, "outflow"), H, 1e-13);
}

// The Stokes start of a viscoelastic fluid: the Newtonian (viscosity 1) Poiseuille flow, exact,
// with the relaxed conformation (log M = 0) and zero velocity gradient.
TEST(FlowBoundaries, StokesStartInARotatedChannel) {
  FluidOptions fluid;
  fluid.model = FluidModel::OldroydB;
  fluid.log_conformation = true;
  fluid.Wi = 0.5;
  fluid.beta = 0.59;
  FlowBoundaries bc;
  bc.inflows = {{"inflow"}, {"outflow", true, {0, 0}, -1.0}};
  bc.walls = {"bottom", "top"};
  FlowOnMesh p(channel(3, 1, 6, 3, rotation(30)), fluid, bc);
  const Vector u = p.stokes();
  const double a = std::numbers::pi / 6;
  const auto& xc = p.mesh().node(p.mesh().element(0)[4]);
  const PoiseuilleError e = poiseuille_error(p, u, 30, 0, 1, std::cos(a) * xc[0] + std::sin(a) * xc[1]);
  EXPECT_LT(e.velocity, 1e-11);
  EXPECT_LT(e.pressure, 1e-10);
  double rest = 0;
  for (int n = 0; n < p.mesh().num_nodes(); ++n)
    if (p.mesh().is_vertex(n))
      for (int c = 0; c < 4; ++c)
        rest = std::max(
            {rest, std::abs(p.value(u, "gradient", n, c)), c < 3 ? std::abs(p.value(u, "conformation", n, c)) : 0.0});
  EXPECT_EQ(rest, 0.0);
}

// Half a channel of half-width 1 with its centreline a symmetry line: the inflow's channel is the
// segment mirrored about its end on the line, u = 1.5 (1 - y'^2); G = 3. Along x and along y.
TEST(FlowBoundaries, HalfChannelWithASymmetryLine) {
  for (double deg : {0.0, 90.0}) {
    const double L = 4;
    FlowBoundaries bc = channel_bc(true);
    bc.walls = {"top"};
    bc.symmetry = {"bottom"};
    FlowOnMesh p(channel(L, 1, 5, 3, rotation(deg)), FluidOptions{}, bc);
    const Vector u = p.solve();
    const PoiseuilleError e = poiseuille_error(p, u, deg, -1, 1, L);
    EXPECT_LT(e.velocity, 1e-11) << deg;
    EXPECT_LT(e.pressure, 1e-10) << deg;
    EXPECT_LT(e.pressure_gradient, 1e-10) << deg;
  }
}

// Fully developed outflows facing -x (flow from right to left) and +y: P = 0 at the outflow.
TEST(FlowBoundaries, PoiseuilleFlowingLeftAndUp) {
  for (double deg : {180.0, 90.0}) {
    const double L = 3;
    FlowOnMesh p(channel(L, 1, 6, 3, rotation(deg)), FluidOptions{}, channel_bc(true));
    const Vector u = p.solve();
    const PoiseuilleError e = poiseuille_error(p, u, deg, 0, 1, L);
    EXPECT_LT(e.velocity, 1e-11) << deg;
    EXPECT_LT(e.pressure, 1e-10) << deg;
    EXPECT_LT(e.pressure_gradient, 1e-10) << deg;
  }
}

// Oldroyd-B: the channel's solution rotated (v -> R v, M -> R M R^T, L -> R L R^T, grad P -> R
// grad P) is the rotated channel's solution: at 30 degrees (traction-free outflow), and at 90 and
// 180 degrees with the fully developed outflow, whose polymer traction uses the boundary's normal.
TEST(FlowBoundaries, OldroydBIsRotationInvariant) {
  FluidOptions fluid;
  fluid.model = FluidModel::OldroydB;
  fluid.kernel.model = FluidModel::OldroydB;
  fluid.Wi = 0.4;
  fluid.beta = 0.59;
  for (double deg : {30.0, 90.0, 180.0}) {
    const bool fd = deg != 30.0;
    FlowOnMesh ref(channel(3, 1, 6, 3, rotation(0)), fluid, channel_bc(fd));
    FlowOnMesh rot(channel(3, 1, 6, 3, rotation(deg)), fluid, channel_bc(fd));
    const Vector u0 = ref.solve(true), u1 = rot.solve(true);
    const double a = deg * std::numbers::pi / 180;
    const double c = deg == 90    ? 0.0
                     : deg == 180 ? -1.0
                                  : std::cos(a),
                 s = deg == 90    ? 1.0
                     : deg == 180 ? 0.0
                                  : std::sin(a);
    double err = 0, scale = 0;
    auto compare = [&](double expected, double got) {
      err = std::max(err, std::abs(expected - got));
      scale = std::max(scale, std::abs(expected));
    };
    for (int n = 0; n < ref.mesh().num_nodes(); ++n) {
      const double vx = ref.value(u0, "velocity", n, 0), vy = ref.value(u0, "velocity", n, 1);
      compare(c * vx - s * vy, rot.value(u1, "velocity", n, 0));
      compare(s * vx + c * vy, rot.value(u1, "velocity", n, 1));
      if (!ref.mesh().is_vertex(n)) continue;
      const double m[3] = {ref.value(u0, "conformation", n, 0), ref.value(u0, "conformation", n, 1),
                           ref.value(u0, "conformation", n, 2)};
      compare(c * c * m[0] - 2 * c * s * m[1] + s * s * m[2], rot.value(u1, "conformation", n, 0));
      compare(c * s * (m[0] - m[2]) + (c * c - s * s) * m[1], rot.value(u1, "conformation", n, 1));
      compare(s * s * m[0] + 2 * c * s * m[1] + c * c * m[2], rot.value(u1, "conformation", n, 2));
      double L[2][2], R[2][2] = {{c, -s}, {s, c}};
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) L[i][j] = ref.value(u0, "gradient", n, 2 * i + j);
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
          double v = 0;
          for (int k = 0; k < 2; ++k)
            for (int l = 0; l < 2; ++l) v += R[i][k] * L[k][l] * R[j][l];
          compare(v, rot.value(u1, "gradient", n, 2 * i + j));
        }
    }
    for (int e = 0; e < ref.mesh().num_elements(); ++e) {
      const auto P0 = ref.pressure(u0, e), P1 = rot.pressure(u1, e);
      compare(P0[0], P1[0]);
      compare(c * P0[1] - s * P0[2], P1[1]);
      compare(s * P0[1] + c * P0[2], P1[2]);
    }
    std::cout << "Oldroyd-B rotated by " << deg << " degrees: max difference " << err << " (scale " << scale << ")\n";
    EXPECT_LT(err, 1e-10 * scale) << deg << " degrees";
  }
}

// A given uniform inflow (plug flow) of an Oldroyd-B fluid: the velocity at the inflow nodes is
// the given one (0 at the wall corners), the conformation at its vertices relaxed (M = I), and
// what enters leaves through the outflow, to rounding.
TEST(FlowBoundaries, GivenVelocityInflow) {
  FluidOptions fluid;
  fluid.model = FluidModel::OldroydB;
  fluid.Wi = 0.2;
  fluid.beta = 0.59;
  FlowBoundaries bc = channel_bc(true);
  bc.inflows = {{"inflow", false, {1.0, 0.0}}};
  FlowOnMesh p(channel(4, 1, 8, 4, rotation(0)), fluid, bc);
  const Vector u = p.solve();
  for (int n : p.mesh().boundary_nodes("inflow")) {
    const double y = p.mesh().node(n)[1];
    EXPECT_NEAR(p.value(u, "velocity", n, 0), y == 0.0 || y == 1.0 ? 0.0 : 1.0, 1e-14) << y;
    EXPECT_NEAR(p.value(u, "velocity", n, 1), 0.0, 1e-14);
    if (!p.mesh().is_vertex(n)) continue;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(p.value(u, "conformation", n, c), c == 1 ? 0.0 : 1.0, 1e-14);
  }
  const double in = p.flow_rate(u, "inflow"), out = p.flow_rate(u, "outflow");
  EXPECT_LT(in, -0.8);  // the plug less its wall corners' share
  EXPECT_NEAR(in + out, 0.0, 1e-13);
}

// Plane Couette flow u = U y, P = P0 (bottom wall, top wall driven at (U, 0)), its traction
// sigma n given at both ends: sigma = [[-P0, U], [U, -P0]].
TEST(FlowBoundaries, CouetteFlowWithDrivenWallAndTractions) {
  const double U = 2.0, P0 = 0.7;
  FlowBoundaries bc;
  bc.walls = {"bottom"};
  bc.driven_walls = {{"top", {U, 0.0}}};
  bc.tractions = {{"inflow", {P0, -U}}, {"outflow", {-P0, U}}};
  FlowOnMesh p(channel(2, 1, 4, 3, rotation(0)), FluidOptions{}, bc);
  const Vector u = p.solve();
  double ev = 0, ep = 0;
  for (int n = 0; n < p.mesh().num_nodes(); ++n) {
    ev = std::max(ev, std::abs(p.value(u, "velocity", n, 0) - U * p.mesh().node(n)[1]));
    ev = std::max(ev, std::abs(p.value(u, "velocity", n, 1)));
  }
  for (int e = 0; e < p.mesh().num_elements(); ++e) {
    const auto P = p.pressure(u, e);
    ep = std::max({ep, std::abs(P[0] - P0), std::abs(P[1]), std::abs(P[2])});
  }
  std::cout << "Couette: max errors velocity " << ev << ", pressure " << ep << "\n";
  EXPECT_LT(ev, 1e-11);
  EXPECT_LT(ep, 1e-11);
  // the traction term: Jacobian zero (finite differences), load - int phi_a t ds, summing to -t |edge|
  const Term& t = p.term("traction");
  ASSERT_EQ(t.num_items(), 3);  // the first traction boundary, "inflow"
  std::vector<double> ul(18, 0.3), r(18);
  for (size_t k = 0; k < ul.size(); ++k) ul[k] = std::sin(double(k));
  EXPECT_LT(test::check_term_jacobian(t, 0, ul).max_relative_error, 1e-12);
  double fx = 0, fy = 0;
  for (int item = 0; item < 3; ++item) {
    ASSERT_TRUE(t.residual(item, ul.data(), r.data()).is_ok());
    for (int a = 0; a < 9; ++a) {
      fx += r[static_cast<size_t>(a)];
      fy += r[static_cast<size_t>(9 + a)];
    }
  }
  EXPECT_NEAR(fx, -P0 * 1.0, 1e-14);
  EXPECT_NEAR(fy, U * 1.0, 1e-14);
}

// The lid-driven cavity: every boundary has a given velocity, so the pressure is pinned at the
// centre of the first element; at the lid's ends the no-slip side walls win. Stokes flow on a
// mesh symmetric about x = 1/2 is symmetric: v_x(1 - x, y) = v_x, v_y(1 - x, y) = -v_y, and
// P(1 - x, y) = -P + const (the flow with the lid reversed is the mirror image).
TEST(FlowBoundaries, LidDrivenCavity) {
  FlowBoundaries bc;
  bc.walls = {"bottom", "left", "right"};
  bc.driven_walls = {{"top", {1.0, 0.0}}};
  FlowOnMesh p(channel(1, 1, 4, 4, rotation(0), {"bottom", "right", "top", "left"}), FluidOptions{}, bc);
  const Vector u = p.solve();
  const Mesh& m = p.mesh();
  std::map<std::pair<long, long>, int> at;
  auto key = [](const Mesh::Point& x) { return std::make_pair(std::lround(x[0] * 1e6), std::lround(x[1] * 1e6)); };
  for (int n = 0; n < m.num_nodes(); ++n) at[key(m.node(n))] = n;
  double asym = 0;
  for (int n = 0; n < m.num_nodes(); ++n) {
    const auto& x = m.node(n);
    const int mirror = at.at(key({1 - x[0], x[1]}));
    asym = std::max({asym, std::abs(p.value(u, "velocity", n, 0) - p.value(u, "velocity", mirror, 0)),
                     std::abs(p.value(u, "velocity", n, 1) + p.value(u, "velocity", mirror, 1))});
    if (x[1] == 1.0) {
      const bool corner = x[0] == 0.0 || x[0] == 1.0;
      EXPECT_NEAR(p.value(u, "velocity", n, 0), corner ? 0.0 : 1.0, 1e-14) << x[0];
      EXPECT_NEAR(p.value(u, "velocity", n, 1), 0.0, 1e-14);
    }
  }
  std::cout << "cavity: mirror asymmetry " << asym << "\n";
  EXPECT_LT(asym, 1e-12);
  EXPECT_GT(std::abs(p.value(u, "velocity", at.at(key({0.5, 0.5})), 0)), 0.05);  // the flow turns
  EXPECT_NEAR(p.pressure(u, 0)[0], 0.0, 1e-14);
  std::vector<double> sums;
  for (int e = 0; e < m.num_elements(); ++e) {
    const auto& xc = m.node(m.element(e)[4]);
    for (int f = 0; f < m.num_elements(); ++f) {
      const auto& yc = m.node(m.element(f)[4]);
      if (std::abs(yc[0] - (1 - xc[0])) < 1e-12 && std::abs(yc[1] - xc[1]) < 1e-12)
        sums.push_back(p.pressure(u, e)[0] + p.pressure(u, f)[0]);
    }
  }
  ASSERT_EQ(sums.size(), 16u);
  for (double s : sums) EXPECT_NEAR(s, sums[0], 1e-10);
}

// A cross: two inflows (mean 1 from the left, 0.5 from below), a fully developed outflow on the
// right and a traction-free one on top. The discrete flow rates balance to rounding.
TEST(FlowBoundaries, SeveralInflowsAndOutflowsConserveMass) {
  BlockMeshBuilder b;
  auto block = [&](const char* name, double x0, double y0, double w, double h, std::array<std::string, 4> sides) {
    return b.add_block({name, "fluid", 2, 2, Grading{}, Grading{},
                        [=](double s, double t) {
                          return Mesh::Point{x0 + w * s, y0 + h * t};
                        },
                        sides});
  };
  const int c = block("centre", 0, 0, 1, 1, {"", "", "", ""});
  const int l = block("left", -2, 0, 2, 1, {"wall", "", "wall", "west"});
  const int r = block("right", 1, 0, 2, 1, {"wall", "east", "wall", ""});
  const int d = block("down", 0, -2, 1, 2, {"south", "wall", "", "wall"});
  const int u = block("up", 0, 1, 1, 2, {"", "wall", "north", "wall"});
  b.connect(l, Side::Right, c, Side::Left);
  b.connect(c, Side::Right, r, Side::Left);
  b.connect(d, Side::Top, c, Side::Bottom);
  b.connect(c, Side::Top, u, Side::Bottom);
  FlowBoundaries bc;
  bc.inflows = {{"west"}, {"south", true, {0, 0}, 0.5}};
  bc.outflows = {{"east", true}, {"north", false}};
  bc.walls = {"wall"};
  FluidOptions fluid;
  fluid.Re = 5;
  fluid.inertia = true;
  fluid.kernel.inertia = true;
  FlowOnMesh p(b.build(), fluid, bc);
  const Vector s = p.solve();
  const double west = p.flow_rate(s, "west"), south = p.flow_rate(s, "south");
  const double east = p.flow_rate(s, "east"), north = p.flow_rate(s, "north");
  EXPECT_NEAR(west, -1.0, 1e-13);
  EXPECT_NEAR(south, -0.5, 1e-13);
  EXPECT_GT(east, 0.1);
  EXPECT_GT(north, 0.1);
  std::cout << "cross: flow rates west " << west << " south " << south << " east " << east << " north " << north
            << ", sum " << west + south + east + north << "\n";
  EXPECT_NEAR(west + south + east + north, 0.0, 1e-12);
}
