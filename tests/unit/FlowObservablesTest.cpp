// The flow observables are functionals of the state: on fields whose integrals are known in
// closed form they must give those values to rounding. Exact Poiseuille flow (Q2 velocity, P1
// pressure: the discrete solution itself on straight elements) gives the wall shear force G H L,
// the flow rate 2 U H, the pressure drop G L and a Couette correction of 0; a Q2 stream function
// is recovered exactly from its curl; a wall shear stress linear along the wall has its zero
// where the interpolation puts it; min m1 is where the conformation is set smallest.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>

#include "core/Assembler.hpp"
#include "core/BlockMeshBuilder.hpp"
#include "problems/components/Composition.hpp"
#include "problems/components/FlowEquations.hpp"
#include "problems/cylinder/CylinderProblem.hpp"
#include "problems/flow/FlowObservables.hpp"

using namespace keller;
using Kind = FlowObservableSpec::Kind;

namespace {

constexpr double kL = 3.0, kH = 1.0, kU = 1.0;

// A straight channel 0 < x < L on nx x ny graded rectangles: the full channel -H < y < H with
// walls "top" and "bottom", or its upper half 0 < y < H with the symmetry line "axis".
struct Channel {
  Mesh mesh;
  ParameterSet params;
  std::unique_ptr<FlowEquations> flow;
  ComposedSystem system;
  std::unique_ptr<Assembler> assembler;

  Channel(bool half, FluidOptions fluid = {}) {
    const double y0 = half ? 0.0 : -kH;
    BlockMeshBuilder b;
    b.add_block({"channel",
                 "fluid",
                 6,
                 4,
                 Grading::start(2.0),
                 Grading::both_ends(1.5),
                 [=](double s, double t) {
                   return Mesh::Point{kL * s, y0 + (kH - y0) * t};
                 },
                 {half ? "axis" : "bottom", "outflow", "top", "inflow"}});
    mesh = b.build();
    FlowBoundaries bc;
    bc.walls = half ? std::vector<std::string>{"top"} : std::vector<std::string>{"top", "bottom"};
    if (half) bc.symmetry = {"axis"};
    bc.inflows = {{"inflow"}};
    bc.outflows = {{"outflow"}};
    flow = std::make_unique<FlowEquations>(mesh, "fluid", fluid, bc, params, -1);
    system = Composition().add(*flow).build(mesh, params);
    assembler = std::make_unique<Assembler>(system.dofs->size(), system.terms());
  }
  const DofMap& dofs() const { return *system.dofs; }
  FlowConstraints constraints(bool half) const {
    return {system.dirichlet->dofs(), half ? std::vector<std::string>{"axis"} : std::vector<std::string>{}};
  }

  // Poiseuille flow u = (3U/2)(1 - y^2/H^2), P = G (L - x) + jump (x < x_jump), G = 3 U / H^2
  // (eta0 = 1): nodal Q2 velocity, P1disc pressure about each element's centre node.
  Vector poiseuille(double jump = 0, double x_jump = 0) const {
    Vector u = Vector::Zero(dofs().size());
    if (flow->options().viscoelastic()) flow->initial_guess(u);
    const int fv = dofs().field_index("velocity"), fp = dofs().field_index("pressure");
    for (int n = 0; n < mesh.num_nodes(); ++n) {
      const double y = mesh.node(n)[1];
      u[dofs().node_dof(fv, n, 0)] = 1.5 * kU * (1 - y * y / (kH * kH));
      u[dofs().node_dof(fv, n, 1)] = 0;
    }
    const double G = 3 * kU / (kH * kH);
    for (int e = 0; e < mesh.num_elements(); ++e) {
      const double xc = mesh.node(mesh.element(e)[4])[0];
      u[dofs().element_dof(fp, e, 0, 0)] = G * (kL - xc) + (xc < x_jump ? jump : 0.0);
      u[dofs().element_dof(fp, e, 1, 0)] = -G;
      u[dofs().element_dof(fp, e, 2, 0)] = 0;
    }
    return u;
  }
};

FlowObservableSpec spec(std::string name, Kind kind, std::string boundary, std::string other = "", int component = 0) {
  FlowObservableSpec s;
  s.name = std::move(name);
  s.kind = kind;
  s.boundary = std::move(boundary);
  s.other = std::move(other);
  s.component = component;
  return s;
}

std::vector<double> evaluate(const Channel& c, const FlowObservables& obs, const Vector& u) {
  Vector R;
  EXPECT_TRUE(c.assembler->weak_residual(u, R).is_ok());
  std::vector<double> v;
  EXPECT_TRUE(obs.evaluate(u, obs.needs_reaction() ? &R : nullptr, v).is_ok());
  return v;
}

}  // namespace

// Per wall F_x = -int sigma_xy n_y ds = G H L; on the top wall F_y = int P ds = G L^2 / 2; the
// inflow (velocity given: a reaction whose corner nodes it shares with the walls) is pushed back
// by P(0) 2H = G L 2H, so that the forces on the whole boundary balance; the outflow's velocity
// is free in x (a surface integral) and P = 0 there.
TEST(FlowObservables, PoiseuilleForcesFlowRatesAndPressuresAreExact) {
  Channel c(false);
  const double G = 3 * kU / (kH * kH);
  std::vector<FlowObservableSpec> specs = {spec("top_x", Kind::Force, "top"),
                                           spec("bottom_x", Kind::Force, "bottom"),
                                           spec("top_y", Kind::Force, "top", "", 1),
                                           spec("inflow_x", Kind::Force, "inflow"),
                                           spec("outflow_x", Kind::Force, "outflow"),
                                           spec("Q_out", Kind::FlowRate, "outflow"),
                                           spec("Q_in", Kind::FlowRate, "inflow"),
                                           spec("p_in", Kind::MeanPressure, "inflow"),
                                           spec("p_out", Kind::MeanPressure, "outflow"),
                                           spec("dp", Kind::PressureDrop, "inflow", "outflow")};
  FlowObservables obs(c.mesh, c.dofs(), *c.flow, c.params, c.constraints(false), specs);
  EXPECT_TRUE(obs.needs_reaction());
  const Vector u = c.poiseuille();
  // the exact state is the discrete solution: the residual vanishes
  Vector F;
  ASSERT_TRUE(c.assembler->residual(u, F).is_ok());
  EXPECT_LT(F.lpNorm<Eigen::Infinity>(), 1e-12);
  const std::vector<double> v = evaluate(c, obs, u);
  const double tol = 1e-12 * G * kL * kL;
  EXPECT_NEAR(v[0], G * kH * kL, tol);
  EXPECT_NEAR(v[1], G * kH * kL, tol);
  EXPECT_NEAR(v[2], G * kL * kL / 2, tol);
  EXPECT_NEAR(v[3], -G * kL * 2 * kH, tol);
  EXPECT_NEAR(v[4], 0.0, tol);
  EXPECT_NEAR(v[5], 2 * kU * kH, 1e-13);
  EXPECT_NEAR(v[6], -2 * kU * kH, 1e-13);
  EXPECT_NEAR(v[7], G * kL, tol);
  EXPECT_NEAR(v[8], 0.0, tol);
  EXPECT_NEAR(v[9], G * kL, tol);
}

// The reaction and the surface integral are two functionals of one state; on the exact state
// both are the exact force, on a perturbed one they differ (so the test sees which is used).
TEST(FlowObservables, ReactionAndSurfaceIntegralAgreeOnTheExactState) {
  Channel c(false);
  std::vector<FlowObservableSpec> specs;
  for (const char* b : {"top", "bottom", "inflow"})
    for (int comp = 0; comp < 2; ++comp) {
      FlowObservableSpec r = spec(std::string(b) + "_r" + std::to_string(comp), Kind::Force, b, "", comp);
      FlowObservableSpec s = r;
      s.name = std::string(b) + "_s" + std::to_string(comp);
      s.surface_integral = true;
      specs.push_back(r);
      specs.push_back(s);
    }
  FlowObservables obs(c.mesh, c.dofs(), *c.flow, c.params, c.constraints(false), specs);
  const std::vector<double> v = evaluate(c, obs, c.poiseuille());
  for (size_t i = 0; i < v.size(); i += 2) EXPECT_NEAR(v[i], v[i + 1], 1e-11) << specs[i].name;
  Vector u = c.poiseuille();
  const int fv = c.dofs().field_index("velocity");
  for (int n = 0; n < c.mesh.num_nodes(); ++n) u[c.dofs().node_dof(fv, n, 0)] *= 1 + 0.1 * c.mesh.node(n)[0];
  const std::vector<double> w = evaluate(c, obs, u);
  EXPECT_GT(std::abs(w[0] - w[1]), 1e-3);
}

// The same flow in the half channel on the symmetry line: U H through the outflow; a straight
// channel has no Couette correction wherever its "contraction plane" is, and an extra pressure
// drop delta upstream of it is a correction delta / (2 tau_w), tau_w = G H.
TEST(FlowObservables, CouetteCorrectionOfAStraightChannel) {
  for (bool half : {false, true}) {
    Channel c(half);
    FlowObservableSpec C = spec("C", Kind::CouetteCorrection, "inflow", "outflow");
    C.origin = {1.3, 0.0};
    FlowObservables obs(c.mesh, c.dofs(), *c.flow, c.params, c.constraints(half),
                        {C, spec("Q", Kind::FlowRate, "outflow")});
    EXPECT_FALSE(obs.needs_reaction());
    std::vector<double> v;
    ASSERT_TRUE(obs.evaluate(c.poiseuille(), nullptr, v).is_ok());
    EXPECT_NEAR(v[0], 0.0, 1e-12) << (half ? "half" : "full");
    EXPECT_NEAR(v[1], (half ? 1 : 2) * kU * kH, 1e-13);
    const double delta = 0.7, G = 3 * kU / (kH * kH);
    ASSERT_TRUE(obs.evaluate(c.poiseuille(delta, 1.3), nullptr, v).is_ok());
    EXPECT_NEAR(v[0], delta / (2 * G * kH), 1e-12);
  }
}

// An Oldroyd-B fluid in fully developed flow: the polymer carries (1 - beta) of the shear
// stress, the total is still G H per length of wall with G = 3 U / H^2 (eta0 = 1).
TEST(FlowObservables, ViscoelasticWallForceIncludesThePolymerStress) {
  FluidOptions fluid;
  fluid.model = FluidModel::OldroydB;
  fluid.Wi = 0.3;
  fluid.beta = 0.2;
  Channel c(false, fluid);
  FlowObservableSpec s = spec("top_s", Kind::Force, "top");
  s.surface_integral = true;
  FlowObservables obs(c.mesh, c.dofs(), *c.flow, c.params, c.constraints(false),
                      {spec("top_r", Kind::Force, "top"), s});
  const std::vector<double> v = evaluate(c, obs, c.poiseuille());
  const double G = 3 * kU / (kH * kH);
  EXPECT_NEAR(v[0], G * kH * kL, 1e-11);
  EXPECT_NEAR(v[1], G * kH * kL, 1e-11);
}

namespace {

// A velocity field set from functions at the nodes (pressure and the rest zero).
Vector velocity_field(const Channel& c, const std::function<double(double, double)>& vx,
                      const std::function<double(double, double)>& vy) {
  Vector u = Vector::Zero(c.dofs().size());
  const int fv = c.dofs().field_index("velocity");
  for (int n = 0; n < c.mesh.num_nodes(); ++n) {
    const Mesh::Point& x = c.mesh.node(n);
    u[c.dofs().node_dof(fv, n, 0)] = vx(x[0], x[1]);
    u[c.dofs().node_dof(fv, n, 1)] = vy(x[0], x[1]);
  }
  return u;
}

double reattachment(const Channel& c, const Vector& u, Mesh::Point origin, double scale = 1.0) {
  FlowObservableSpec s = spec("XR", Kind::Reattachment, "top");
  s.origin = origin;
  s.scale = scale;
  FlowObservables obs(c.mesh, c.dofs(), *c.flow, c.params, c.constraints(true), {s});
  std::vector<double> v;
  EXPECT_TRUE(obs.evaluate(u, nullptr, v).is_ok());
  return v[0];
}

}  // namespace

// v = ((x - x0)(H - y), 0) has the wall shear stress -(x - x0) on y = H: linear along the wall,
// so the interpolated zero is x0 exactly, measured from either end of the wall. With two zeros
// x1 < x2 ((x - x1)(x - x2)(H - y)) the one met first from the far end counts: x2 from (0, H)
// (within the linear interpolation's error, h^2/8 |tau''| / |tau'| on the graded mesh's largest
// element h = 0.75), L - x1 from (L, H). A shear stress of one sign is no vortex: 0.
TEST(FlowObservables, ReattachmentIsWhereTheWallShearStressChangesSign) {
  Channel c(true);
  const double x0 = 1.37;
  const Vector lin = velocity_field(
      c, [&](double x, double y) { return (x - x0) * (kH - y); }, [](double, double) { return 0.0; });
  EXPECT_NEAR(reattachment(c, lin, {0.0, kH}), x0, 1e-13);
  EXPECT_NEAR(reattachment(c, lin, {kL, kH}), kL - x0, 1e-13);
  EXPECT_NEAR(reattachment(c, lin, {0.0, kH}, 0.5), 0.5 * x0, 1e-13);
  const double x1 = 0.4, x2 = 2.1;
  const Vector quad = velocity_field(
      c, [&](double x, double y) { return (x - x1) * (x - x2) * (kH - y); }, [](double, double) { return 0.0; });
  const double bound = 0.75 * 0.75 / 8 * 2 / (x2 - x1);
  EXPECT_NEAR(reattachment(c, quad, {0.0, kH}), x2, bound);
  EXPECT_NEAR(reattachment(c, quad, {kL, kH}), kL - x1, bound);
  const Vector none = velocity_field(
      c, [&](double x, double y) { return (1 + x) * (kH - y); }, [](double, double) { return 0.0; });
  EXPECT_EQ(reattachment(c, none, {0.0, kH}), 0.0);
}

// psi = x^2 y^2 is Q2 on the channel's rectangles; its curl v = (2 x^2 y, -2 x y^2) is Q2 too and
// gives psi back to rounding, 0 on the axis y = 0; the extremum over the nodes in a box is the
// largest (smallest) x^2 y^2 there; divided by the flow rate through the outflow, int_0^H 2 L^2 y
// dy = L^2 H^2.
TEST(FlowObservables, StreamFunctionOfAQ2FieldIsExact) {
  Channel c(true);
  const Vector u = velocity_field(
      c, [](double x, double y) { return 2 * x * x * y; }, [](double x, double y) { return -2 * x * y * y; });
  const std::array<double, 4> box{0.2, 1.9, 0.1, 0.8};
  double largest = -1, smallest = 1e9;
  for (const Mesh::Point& p : c.mesh.nodes())
    if (p[0] >= box[0] && p[0] <= box[1] && p[1] >= box[2] && p[1] <= box[3]) {
      largest = std::max(largest, p[0] * p[0] * p[1] * p[1]);
      smallest = std::min(smallest, p[0] * p[0] * p[1] * p[1]);
    }
  FlowObservableSpec mx = spec("psi_max", Kind::StreamFunctionExtremum, "axis");
  mx.region = box;
  FlowObservableSpec mn = mx;
  mn.name = "psi_min";
  mn.maximum = false;
  FlowObservableSpec q = mx;
  q.name = "psi_max_per_Q";
  q.other = "outflow";
  FlowObservables obs(c.mesh, c.dofs(), *c.flow, c.params, c.constraints(true), {mx, mn, q});
  std::vector<double> v;
  ASSERT_TRUE(obs.evaluate(u, nullptr, v).is_ok());
  EXPECT_NEAR(v[0], largest, 1e-12);
  EXPECT_NEAR(v[1], smallest, 1e-12);
  EXPECT_NEAR(v[2], largest / (kL * kL * kH * kH), 1e-13);
  EXPECT_GT(largest - smallest, 0.5);
}

// Mxx = 0.5 + (x - xs)^2 + (y - ys)^2 with Myy = 2, Mxy = 0, Mzz = 1 has m1 = Mxx, least (0.5)
// at the vertex (xs, ys); its place is that vertex's.
TEST(FlowObservables, MinM1AndWhereItIs) {
  FluidOptions fluid;
  fluid.model = FluidModel::OldroydB;
  Channel c(true, fluid);
  const int fm = c.dofs().field_index("conformation");
  Vector u = Vector::Zero(c.dofs().size());
  int vertex = -1;
  for (int n = 0; n < c.mesh.num_nodes() && vertex < 0; ++n)
    if (c.mesh.is_vertex(n) && c.mesh.node(n)[0] > 1 && c.mesh.node(n)[1] > 0.3) vertex = n;
  const Mesh::Point s = c.mesh.node(vertex);
  for (int n = 0; n < c.mesh.num_nodes(); ++n) {
    if (c.dofs().node_dof(fm, n, 0) < 0) continue;
    const Mesh::Point& x = c.mesh.node(n);
    u[c.dofs().node_dof(fm, n, 0)] = 0.5 + (x[0] - s[0]) * (x[0] - s[0]) + (x[1] - s[1]) * (x[1] - s[1]);
    u[c.dofs().node_dof(fm, n, 2)] = 2.0;
  }
  FlowObservableSpec m = spec("min_m1", Kind::MinM1, "");
  FlowObservableSpec mx = spec("min_m1_x", Kind::MinM1, "", "", 1), my = spec("min_m1_y", Kind::MinM1, "", "", 2);
  FlowObservables obs(c.mesh, c.dofs(), *c.flow, c.params, c.constraints(true), {m, mx, my});
  std::vector<double> v;
  ASSERT_TRUE(obs.evaluate(u, nullptr, v).is_ok());
  EXPECT_DOUBLE_EQ(v[0], 0.5);
  EXPECT_EQ(v[1], s[0]);
  EXPECT_EQ(v[2], s[1]);
}

// Every refusal names the observable and what to change.
TEST(FlowObservables, BadSpecsAreRefusedNamingTheObservable) {
  Channel c(true);
  auto message = [&](const FlowObservableSpec& s, const std::string& extra_name = "") {
    std::vector<FlowObservableSpec> specs = {s};
    if (!extra_name.empty()) specs.push_back(spec(extra_name, Kind::FlowRate, "outflow"));
    try {
      FlowObservables obs(c.mesh, c.dofs(), *c.flow, c.params, c.constraints(true), specs);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  auto has = [](const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; };
  EXPECT_TRUE(has(message(spec("F", Kind::Force, "cylinder")),
                  "observable 'F' (force): the boundary 'cylinder' (the boundary the force is on) is not in the "
                  "mesh (its boundaries: axis, inflow, outflow, top)"));
  EXPECT_TRUE(has(message(spec("F", Kind::Force, "top", "", 2)), "component must be 0 (x) or 1 (y)"));
  EXPECT_TRUE(has(message(spec("dp", Kind::PressureDrop, "inflow")), "'dp' (pressure-drop): needs a boundary (to)"));
  EXPECT_TRUE(has(message(spec("Q", Kind::FlowRate, "inflow"), "Q"), "the name is used by another observable"));
  FlowObservableSpec r = spec("XR", Kind::Reattachment, "top");
  r.origin = {1.0, kH};
  EXPECT_TRUE(has(message(r), "the origin (1.000000, 1.000000) must be an end of the wall 'top' (its ends: "));
  FlowObservableSpec box = spec("psi", Kind::StreamFunctionExtremum, "axis");
  box.region = {0.01, 0.02, 0.3, 0.31};
  EXPECT_TRUE(has(message(box), "the region holds no node of the fluid's mesh"));
  EXPECT_TRUE(has(message(spec("m", Kind::MinM1, "")), "the fluid is Newtonian: it has no conformation"));
  FluidOptions fluid;
  fluid.model = FluidModel::OldroydB;
  Channel ve(true, fluid);
  FlowObservableSpec place = spec("min_m1_x", Kind::MinM1, "", "", 1);
  place.monitor = true;
  EXPECT_THROW(FlowObservables(ve.mesh, ve.dofs(), *ve.flow, ve.params, ve.constraints(true), {place}),
               std::invalid_argument);
  for (Kind k : {Kind::Force, Kind::FlowRate, Kind::MeanPressure, Kind::PressureDrop, Kind::CouetteCorrection,
                 Kind::Reattachment, Kind::StreamFunctionExtremum, Kind::MinM1})
    EXPECT_EQ(flow_observable_kind(to_string(k)), k);
  try {
    flow_observable_kind("drag");
    ADD_FAILURE() << "an unknown kind was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(has(e.what(),
                    "unknown observable kind 'drag' (force, flow-rate, mean-pressure, pressure-drop, "
                    "couette-correction, reattachment, stream-function-extremum, min-m1)"));
  }
}

// On the built-in cylinder's mesh and state the force on "cylinder" is its drag: the reaction is
// CylinderProblem::drag and the surface integral its K_surface, both halves (scale 2), to the
// last digit (the same sums in the same order), on a state that is not a solution (where the
// two differ).
TEST(FlowObservables, CylinderForceIsTheBuiltInDrag) {
  CylinderOptions o;
  o.fluid.model = FluidModel::OldroydB;
  o.fluid.Wi = 0.4;
  CylinderProblem p(o);
  Vector u = p.initial_guess();
  for (int i = 0; i < u.size(); ++i) u[i] += 0.01 * std::sin(0.37 * i);
  const int fv = p.dofs().field_index("velocity");
  FlowConstraints given;
  for (const char* b : {"cylinder", "wall", "inflow"})
    for (int n : p.mesh().boundary_nodes(b))
      for (int comp = 0; comp < 2; ++comp) given.given.push_back(p.dofs().node_dof(fv, n, comp));
  for (int n : p.mesh().boundary_nodes("symmetry")) given.given.push_back(p.dofs().node_dof(fv, n, 1));
  given.symmetry = {"symmetry"};
  FlowObservableSpec r = spec("K", Kind::Force, "cylinder");
  r.scale = 2;
  FlowObservableSpec s = r;
  s.name = "K_surface";
  s.surface_integral = true;
  FlowObservables obs(p.mesh(), p.dofs(), p.flow(), p.parameters(), given, {r, s});
  Vector R;
  ASSERT_TRUE(p.assembler().weak_residual(u, R).is_ok());
  std::vector<double> v;
  ASSERT_TRUE(obs.evaluate(u, &R, v).is_ok());
  const CylinderProblem::DragTerms d = p.drag_terms(u);
  EXPECT_EQ(v[0], d.reaction);
  EXPECT_EQ(v[1], d.surface);
  EXPECT_GT(std::abs(d.reaction - d.surface), 1.0);
}
