#include "problems/channel/CollapsibleChannelProblem.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/ElementGeometry.hpp"
#include "problems/components/Composition.hpp"
#include "problems/kernels/ConformationTransport.hpp"
#include "problems/kernels/FlowParameters.hpp"
#include "problems/kernels/Momentum.hpp"
#include "problems/kernels/MovingGeometry.hpp"

namespace keller {

void CollapsibleOptions::declare(SceneSchema& s) {
  declare_channel_mesh_keys(s);
  FluidOptions::declare(s, OwensParameters().beta(), 0.1);
  MeshMotionOptions::declare(s);
  s.real("parameters.Gamma", 4.95e-4, "Gamma = eta0 U0 / (G W): wall elasticity, and the mean inflow velocity",
         Range::positive());
  s.real("parameters.t", 0.4, "wall thickness t (units of W)",
         Range::between(SolidWall::min_thickness, SolidWall::max_thickness));
  s.real("parameters.Pe", 0.04, "external pressure on the top of the wall (units of G)");
  s.section("dynamics", "the time-dependent form B du/dt = -F (stability, keller evolve): docs/dynamics.md");
  s.string("dynamics.mass_matrix", "moving-wall",
           "moving-wall: the physical form, time derivatives at fixed points (ALE) and v = dx/dt on the interface; "
           "fixed-wall: time derivatives of the flow fields at the nodes, v = 0 on the interface (the wall follows "
           "quasi-statically, no kinematics: growth rates and frequencies not those of the coupled system)",
           {"fixed-wall", "moving-wall"});
  s.real("dynamics.wall_density_ratio", 0.0,
         "rho_s / rho: > 0 gives the wall inertia (the wall velocity becomes an unknown; needs mass_matrix = "
         "\"moving-wall\" and parameters.Re > 0); 0: the wall is quasi-static",
         Range::non_negative());
}

CollapsibleOptions CollapsibleOptions::from_scene(const Scene& scene) {
  CollapsibleOptions o;
  o.geometry = channel_geometry_from(scene);
  o.geometry.thickness = scene.real("parameters.t");
  o.mesh = channel_mesh_spec_from(scene);
  o.fluid = FluidOptions::from_scene(scene);
  o.motion = MeshMotionOptions::from_scene(scene);
  o.Gamma = scene.real("parameters.Gamma");
  o.Pe = scene.real("parameters.Pe");
  o.moving_wall_dynamics = scene.string("dynamics.mass_matrix") == "moving-wall";
  o.wall_density_ratio = scene.real("dynamics.wall_density_ratio");
  o.validate();
  return o;
}

void CollapsibleOptions::validate() const {
  if (wall_density_ratio > 0 && !moving_wall_dynamics)
    throw std::invalid_argument(
        "dynamics.wall_density_ratio > 0 needs dynamics.mass_matrix = \"moving-wall\" (the wall's inertia "
        "belongs to the physical time-dependent form)");
  if (wall_density_ratio > 0 && !(fluid.Re > 0))
    throw std::invalid_argument(
        "dynamics.wall_density_ratio > 0 needs parameters.Re > 0 (the wall's inertia is the density ratio times "
        "the fluid's, Re / Gamma)");
}

CollapsibleChannelProblem::CollapsibleChannelProblem(const CollapsibleOptions& options)
    : options_(options), mesh_(build_channel_mesh(options.geometry, options.mesh, true)) {
  options_.validate();
  const ChannelGeometry& g = options_.geometry;
  iGamma_ =
      params_.add("Gamma", options_.Gamma, "wall elasticity parameter (the mean inflow velocity)", Range::positive());
  FlowBoundaries bc;
  bc.inflows = {{"inflow"}};
  bc.outflows = {{"outflow"}};
  bc.walls = {"bottom_wall", "top_wall"};
  if (options_.moving_wall_dynamics)
    bc.moving_walls = {"interface"};
  else
    bc.walls.push_back("interface");
  FluidOptions fluid = options_.fluid;
  fluid.kernel.ale = options_.moving_wall_dynamics;
  flow_ = std::make_unique<FlowEquations>(mesh_, "fluid", fluid, bc, params_, iGamma_);
  wall_ =
      std::make_unique<SolidWall>(mesh_, WallGeometry{g.upstream_length, g.upstream_length + g.deformable_length, 1.0},
                                  g.thickness, options_.Pe, params_);
  motion_ = std::make_unique<FluidMeshMotion>(mesh_, "fluid", options_.motion);
  if (options_.wall_density_ratio > 0) {
    // rho_s W^2 G / eta0^2 = (rho_s / rho) Re / Gamma: the fluid's inertia coefficient times the ratio
    const int iRe = params_.index("Re"), iG = iGamma_;
    const double ratio = options_.wall_density_ratio;
    wall_->set_inertia([ratio, iRe, iG](const ParameterSet& p) { return ratio * p.value(iRe) / p.value(iG); });
  }

  // the node positions are shared: the solid's equilibrium governs its nodes (the interface
  // included), the mesh equations the other fluid nodes
  ComposedSystem system = Composition()
                              .add(*flow_)
                              .share({"position", Basis::Q2, {"x", "y"}, {"fluid", "solid"}})
                              .add(*wall_)
                              .add(*motion_)
                              .build(mesh_, params_);
  dofs_ = std::move(system.dofs);
  dirichlet_ = system.dirichlet;

  // the fluid's reaction at each interface node goes to the solid's row of that node
  interface_nodes_ = wall_->interface_nodes();
  const int fv = dofs_->field_index("velocity"), fx = dofs_->field_index("position");
  std::vector<std::pair<int, int>> redirects;
  for (int n : interface_nodes_)
    for (int c = 0; c < 2; ++c) {
      const int to = dofs_->node_dof(fx, n, c);
      if (!dirichlet_->constrains(to)) redirects.emplace_back(dofs_->node_dof(fv, n, c), to);
    }
  assemble(dofs_->size(), system.terms(), redirects);
  deformed_ = mesh_;
  declare_quantities();
}

double CollapsibleChannelProblem::residual_scale() const { return params_.value(iGamma_); }

std::vector<Problem::Homotopy> CollapsibleChannelProblem::homotopies() const {
  // Without external pressure the undeformed channel is nearly the solution; where the flow's own
  // load still deforms a thin wall too far (Owens, t = 0.2, Gamma = 4.95e-4 on M2), the smallest
  // Gamma of the reference range (a tenth of the load) is solved from the guess and continued up;
  // where even that wall is too thin (Owens, t = 0.1 on M2), the reference thickness, whose wall
  // the unloaded flow barely moves, is solved and thinned.
  std::vector<Homotopy> h{{"Pe", 0.0}};
  if (params_.has("Wi")) h.push_back({"Wi", 0.01});
  h.push_back({"Gamma", 4.95e-5});
  h.push_back({"t", ChannelGeometry{}.thickness});
  return h;
}

Vector CollapsibleChannelProblem::initial_guess() {
  // fully developed flow in the undeformed channel; the wall at rest carries the external
  // pressure as its own pressure: P = (1 - pi) I with (1 - pi) = -Pe on the top face
  Vector u = Vector::Zero(size());
  flow_->initial_guess(u);
  motion_->generated_state(*dofs_, u);
  wall_->reference_state(u);
  const int fp = dofs_->field_index("solid_pressure");
  for (int e : wall_->elements())
    u[dofs_->element_dof(fp, e, 0, 0)] = 1.0 + params_.value(wall_->external_pressure_index());
  for (int k = 0; k < dirichlet_->num_items(); ++k) u[dirichlet_->dofs()[k]] = dirichlet_->value(k);
  return u;
}

void CollapsibleChannelProblem::element_positions(const Vector& u, int e, double (&xy)[9][2]) const {
  int d[18];
  dofs_->element_dofs(dofs_->field_index("position"), e, d);
  double x[18];
  for (int k = 0; k < 18; ++k) x[k] = u[d[k]];
  gather_positions(x, xy);
}

double CollapsibleChannelProblem::fluid_pressure(const Vector& u, int e, const double (&xy)[9][2],
                                                 const double (&x)[2]) const {
  const int fp = dofs_->field_index("pressure");
  const double pc[3] = {u[dofs_->element_dof(fp, e, 0, 0)], u[dofs_->element_dof(fp, e, 1, 0)],
                        u[dofs_->element_dof(fp, e, 2, 0)]};
  double psi[3];
  pressure_basis(x, xy[4], psi);
  return pressure_at(pc, psi);
}

std::vector<double> CollapsibleChannelProblem::column_flow_rates(const Vector& u) const {
  const int fv = dofs_->field_index("velocity");
  std::vector<double> out;
  auto line_flow = [&](const MeshBlock& b, int i) {
    double q = 0;
    for (int j = 0; j < b.ny; ++j) {
      const bool right = i == b.nx;
      const int e = b.element(right ? b.nx - 1 : i, j), edge = right ? 1 : 3;
      double xy[9][2];
      element_positions(u, e, xy);
      std::array<EdgeQpGeometry<double>, ref::kEdgeQp> eg;
      if (!map_edge(xy, edge, eg)) return std::numeric_limits<double>::quiet_NaN();
      int vd[18];
      dofs_->element_dofs(fv, e, vd);
      for (int k = 0; k < ref::kEdgeQp; ++k) {
        double vx = 0, vy = 0;
        for (int a = 0; a < 9; ++a) {
          vx += ref::tables().edge_N2[edge][k][a] * u[vd[a]];
          vy += ref::tables().edge_N2[edge][k][a] * u[vd[9 + a]];
        }
        q += (right ? 1.0 : -1.0) * (vx * eg[k].normal[0] + vy * eg[k].normal[1]) * eg[k].wds;
      }
    }
    return q;
  };
  const char* blocks[] = {"upstream", "deformable", "downstream"};
  for (int bi = 0; bi < 3; ++bi) {
    const MeshBlock& b = mesh_.block(blocks[bi]);
    for (int i = bi == 0 ? 0 : 1; i <= b.nx; ++i) out.push_back(line_flow(b, i));
  }
  return out;
}

double CollapsibleChannelProblem::line_pressure(const Vector& u, const MeshBlock& b, int column, int edge) const {
  double pint = 0, len = 0;
  for (int j = 0; j < b.ny; ++j) {
    const int e = b.element(column, j);
    double xy[9][2];
    element_positions(u, e, xy);
    std::array<EdgeQpGeometry<double>, ref::kEdgeQp> eg;
    if (!map_edge(xy, edge, eg)) return std::numeric_limits<double>::quiet_NaN();
    for (const auto& g : eg) {
      pint += fluid_pressure(u, e, xy, g.x) * g.wds;
      len += g.wds;
    }
  }
  return pint / len;
}

double CollapsibleChannelProblem::section_pressure(const Vector& u, int end) const {
  // the pressure is discontinuous between elements: the mean of the two element columns that
  // meet at the line (edge 1 is an element's right side, edge 3 its left)
  const MeshBlock& def = mesh_.block("deformable");
  const MeshBlock& other = mesh_.block(end == 0 ? "upstream" : "downstream");
  if (end == 0) return 0.5 * (line_pressure(u, other, other.nx - 1, 1) + line_pressure(u, def, 0, 3));
  return 0.5 * (line_pressure(u, def, def.nx - 1, 1) + line_pressure(u, other, 0, 3));
}

double CollapsibleChannelProblem::inlet_outlet_pressure_drop(const Vector& u) const {
  const MeshBlock& up = mesh_.block("upstream");
  const MeshBlock& down = mesh_.block("downstream");
  return line_pressure(u, up, 0, 3) - line_pressure(u, down, down.nx - 1, 1);
}

std::array<double, 2> CollapsibleChannelProblem::fluid_force_on_wall(const Vector& u) const {
  Vector F;
  if (!assembler().weak_residual(u, F).is_ok()) return {NAN, NAN};
  const int fv = dofs_->field_index("velocity");
  const int fx = dofs_->field_index("position");
  std::array<double, 2> f = {0, 0};
  for (int n : interface_nodes_)
    for (int c = 0; c < 2; ++c)
      if (!dirichlet_->constrains(dofs_->node_dof(fx, n, c))) f[static_cast<size_t>(c)] -= F[dofs_->node_dof(fv, n, c)];
  return f;
}

std::vector<CollapsibleChannelProblem::InterfaceSample> CollapsibleChannelProblem::interface_samples(
    const Vector& u) const {
  const FluidOptions& fo = options_.fluid;
  const bool ve = fo.viscoelastic();
  const ParameterSet& ps = params_;
  const FlowParameterIndices& index = flow_->parameter_indices();
  const double beta = solvent_viscosity(index, ps.values());
  const int fv = dofs_->field_index("velocity");
  const int fm = ve ? dofs_->field_index("conformation") : -1;
  const int nc = ve ? dofs_->num_components(fm) : 0;
  const MeshBlock& def = mesh_.block("deformable");
  const ref::Tables& tb = ref::tables();
  std::vector<InterfaceSample> out;
  for (int i = 0; i < def.nx; ++i) {
    const int e = def.element(i, def.ny - 1), edge = 2;
    double xy[9][2];
    element_positions(u, e, xy);
    std::array<EdgeQpGeometry<double>, ref::kEdgeQp> eg;
    if (!map_edge(xy, edge, eg)) return {};
    int vd[18], md[16];
    dofs_->element_dofs(fv, e, vd);
    if (ve) dofs_->element_dofs(fm, e, md);
    double vx[9], vy[9];
    for (int a = 0; a < 9; ++a) {
      vx[a] = u[vd[a]];
      vy[a] = u[vd[9 + a]];
    }
    for (int k = 0; k < ref::kEdgeQp; ++k) {
      const EdgeQpGeometry<double>& g = eg[k];
      InterfaceSample smp;
      smp.x = {g.x[0], g.x[1]};
      smp.normal = {g.normal[0], g.normal[1]};
      smp.ds = g.wds;
      double K[2][2];
      velocity_gradient(vx, vy, g.dN2dx, K);
      smp.pressure = fluid_pressure(u, e, xy, g.x);
      const PlaneStress<double> visc = viscous_stress(beta, K);
      smp.extra[0][0] = visc.xx;
      smp.extra[0][1] = smp.extra[1][0] = visc.xy;
      smp.extra[1][1] = visc.yy;
      smp.Mxx = std::numeric_limits<double>::quiet_NaN();
      if (ve) {
        double m[4] = {0, 0, 0, 0};
        for (int c = 0; c < nc; ++c)
          for (int q = 0; q < 4; ++q) m[c] += tb.edge_N1[edge][k][q] * u[md[4 * c + q]];
        const Conformation<double> M =
            nc == 4 ? conformation_of<4>(m, fo.log_conformation) : conformation_of<3>(m, fo.log_conformation);
        const Conformation<double> tp = flow_->polymer_stress_at(u, ps.values(), e, tb.edge_N1[edge][k]);
        smp.extra[0][0] += tp.xx;
        smp.extra[0][1] += tp.xy;
        smp.extra[1][0] += tp.xy;
        smp.extra[1][1] += tp.yy;
        smp.Mxx = M.xx;
      }
      // the test functions of the free interface nodes: all but the clamped corners'
      smp.free_weight = 1.0;
      if (i == 0) smp.free_weight -= tb.edge_N2[edge][k][6];
      if (i == def.nx - 1) smp.free_weight -= tb.edge_N2[edge][k][8];
      out.push_back(smp);
    }
  }
  return out;
}

std::array<double, 2> CollapsibleChannelProblem::interface_traction_integral(const Vector& u) const {
  std::array<double, 2> force = {0, 0};
  const auto samples = interface_samples(u);
  if (samples.empty()) return {NAN, NAN};
  for (const InterfaceSample& s : samples)
    for (int r = 0; r < 2; ++r) {
      const size_t ri = static_cast<size_t>(r);
      const double Tn = (s.extra[r][0] - (r == 0 ? s.pressure : 0.0)) * s.normal[0] +
                        (s.extra[r][1] - (r == 1 ? s.pressure : 0.0)) * s.normal[1];
      force[ri] -= s.free_weight * Tn * s.ds;
    }
  return force;
}

void CollapsibleChannelProblem::declare_quantities() {
  Quantities& o = observables_;
  o.add("dx_max", [this](const Vector& u) { return wall_->max_deflection(u)[0]; });
  o.add("dy_max", [this](const Vector& u) { return wall_->max_deflection(u)[1]; });
  o.add("gap_min", [this](const Vector& u) {
    double gap = INFINITY;
    for (const auto& p : wall_->interface_shape(u)) gap = std::min(gap, p[1]);
    return gap;
  });
  o.add("dP", [this](const Vector& u) { return section_pressure(u, 0) - section_pressure(u, 1); });
  o.add("dP_inlet_outlet", [this](const Vector& u) { return inlet_outlet_pressure_drop(u); });
  o.add("Q_in", [this](const Vector& u) { return column_flow_rates(u).front(); });
  o.add("Q_out", [this](const Vector& u) { return column_flow_rates(u).back(); });
  o.add("area_change", [this](const Vector& u) { return wall_->area(u) - wall_->reference_area(); });
  o.add("mesh_quality", [this](const Vector& u) { return min_mesh_jacobian(u); });
  o.add("min_detF", [this](const Vector& u) { return wall_->min_jacobian(u); });
  if (!options_.fluid.viscoelastic()) return;
  const auto min_m1 = [this](const Vector& u) { return flow_->conformation_extremes(u).min_m1; };
  const auto at_min_m1 = [this](const Vector& u, int c) {
    return u[dofs_->node_dof(dofs_->field_index("position"), flow_->conformation_extremes(u).min_m1_node, c)];
  };
  o.add("min_m1", min_m1);
  o.add("max_m3", [this](const Vector& u) { return flow_->conformation_extremes(u).max_m3; });
  o.add("x_min_m1", [at_min_m1](const Vector& u) { return at_min_m1(u, 0); });
  o.add("y_min_m1", [at_min_m1](const Vector& u) { return at_min_m1(u, 1); });
  o.add("max_trM", [this](const Vector& u) { return flow_->conformation_extremes(u).max_trace; });
  monitors_.add("min_m1", min_m1);
}

Status CollapsibleChannelProblem::observables(const Vector& u, std::vector<double>& values) {
  observables_.evaluate(u, values);
  return {};
}

Status CollapsibleChannelProblem::monitors(const Vector& u, std::vector<double>& values) {
  monitors_.evaluate(u, values);
  return {};
}

bool CollapsibleChannelProblem::has_observable_gradient(int observable) const {
  const std::vector<std::string> names = observable_names();
  return has_monitor_gradient(0) && observable >= 0 && observable < static_cast<int>(names.size()) &&
         names[static_cast<size_t>(observable)] == "min_m1";
}

Status CollapsibleChannelProblem::observable_gradient(int observable, const Vector& u, Vector& gradient) {
  if (!has_observable_gradient(observable)) return MonitorGradients::observable_gradient(observable, u, gradient);
  return monitor_gradient(0, u, gradient);
}

Status CollapsibleChannelProblem::monitor_places(int monitor, const Vector& u, std::vector<double>& values) {
  if (!options_.fluid.viscoelastic() || monitor != 0)
    throw std::out_of_range("collapsible channel: no monitor " + std::to_string(monitor));
  flow_->m1_places(u, values);
  return {};
}

Status CollapsibleChannelProblem::monitor_place_gradient(int monitor, int place, const Vector& u, Vector& gradient) {
  if (!options_.fluid.viscoelastic() || monitor != 0)
    throw std::out_of_range("collapsible channel: no monitor " + std::to_string(monitor));
  flow_->m1_place_gradient(u, place, gradient);
  return {};
}

SolutionFields CollapsibleChannelProblem::fields(const Vector& u) const {
  // on the deformed configuration
  const int fx = dofs_->field_index("position");
  for (int n = 0; n < mesh_.num_nodes(); ++n)
    deformed_.set_node(n, {u[dofs_->node_dof(fx, n, 0)], u[dofs_->node_dof(fx, n, 1)]});
  SolutionFields f = extract_fields(deformed_, *dofs_, u);
  flow_->add_fields(u, f);
  NodalField disp{"displacement", "Q2", {"dx", "dy"}, {}, Eigen::MatrixXd(mesh_.num_nodes(), 2)};
  for (int n = 0; n < mesh_.num_nodes(); ++n)
    for (int i = 0; i < 2; ++i)
      disp.values(n, i) = deformed_.node(n)[static_cast<size_t>(i)] - mesh_.node(n)[static_cast<size_t>(i)];
  f.nodal.push_back(std::move(disp));
  const auto shape = wall_->interface_shape(u);
  NamedArray iface{"interface_shape",
                   "deformed interface (bottom of the wall), left to right",
                   Eigen::MatrixXd(static_cast<long>(shape.size()), 2),
                   {"x", "y"}};
  for (size_t k = 0; k < shape.size(); ++k) {
    iface.values(static_cast<long>(k), 0) = shape[k][0];
    iface.values(static_cast<long>(k), 1) = shape[k][1];
  }
  f.arrays.push_back(std::move(iface));
  // stresses along the interface at the edge Gauss points (n: the fluid's outward normal, up;
  // tangent s = (n_y, -n_x), downstream)
  const auto samples = interface_samples(u);
  NamedArray prof{"interface_profiles",
                  "along the interface at edge Gauss points: pressure, tangential stress t . tau . n and normal "
                  "extra stress n . tau . n of the fluid (tau = T + P I), M_xx (NaN for a Newtonian fluid)",
                  Eigen::MatrixXd(static_cast<long>(samples.size()), 6),
                  {"x", "y", "p", "tangential_stress", "normal_extra_stress", "Mxx"}};
  for (size_t k = 0; k < samples.size(); ++k) {
    const InterfaceSample& sm = samples[k];
    const double n[2] = {sm.normal[0], sm.normal[1]}, tg[2] = {n[1], -n[0]};
    double tn = 0, nn = 0;
    for (int r = 0; r < 2; ++r)
      for (int c = 0; c < 2; ++c) {
        tn += tg[r] * sm.extra[r][c] * n[c];
        nn += n[r] * sm.extra[r][c] * n[c];
      }
    prof.values.row(static_cast<long>(k)) << sm.x[0], sm.x[1], sm.pressure, tn, nn, sm.Mxx;
  }
  f.arrays.push_back(std::move(prof));
  // across the narrowest gap: the mesh line of the deformable block through the lowest interface node
  const MeshBlock& def = mesh_.block("deformable");
  int col = 0;
  for (int i = 0; i <= 2 * def.nx; ++i)
    if (u[dofs_->node_dof(fx, def.node(i, 2 * def.ny), 1)] < u[dofs_->node_dof(fx, def.node(col, 2 * def.ny), 1)])
      col = i;
  const bool ve = options_.fluid.viscoelastic();
  const int fv = dofs_->field_index("velocity");
  NamedArray gap{"gap_profile",
                 "across the narrowest gap (the mesh line through the lowest interface node), bottom to top",
                 Eigen::MatrixXd(2 * def.ny + 1, 5),
                 {"x", "y", "vx", "vy", "Mxx"}};
  const NodalField* conf = nullptr;
  for (const NodalField& nf : f.nodal)
    if (nf.name == (ve && options_.fluid.log_conformation ? "conformation_M" : "conformation")) conf = &nf;
  for (int j = 0; j <= 2 * def.ny; ++j) {
    const int n = def.node(col, j);
    gap.values.row(j) << u[dofs_->node_dof(fx, n, 0)], u[dofs_->node_dof(fx, n, 1)], u[dofs_->node_dof(fv, n, 0)],
        u[dofs_->node_dof(fv, n, 1)], conf ? conf->values(n, 0) : std::numeric_limits<double>::quiet_NaN();
  }
  f.arrays.push_back(std::move(gap));
  const std::vector<double> q = column_flow_rates(u);
  NamedArray flow{"column_flow_rates",
                  "flow rate through every vertical mesh line, upstream to downstream",
                  Eigen::MatrixXd(static_cast<long>(q.size()), 1),
                  {"Q"}};
  for (size_t k = 0; k < q.size(); ++k) flow.values(static_cast<long>(k), 0) = q[k];
  f.arrays.push_back(std::move(flow));
  return f;
}

std::string CollapsibleChannelProblem::summary() const {
  const FluidOptions& f = options_.fluid;
  return fmt::format(
      "collapsible channel, {}, neo-Hookean wall, elliptic mesh ({} wall nodes); mesh {}: {} elements ({} "
      "fluid + "
      "{} solid), {} nodes; {} unknowns",
      f.describe(), options_.motion.sliding_walls ? "sliding" : "fixed", options_.mesh.name, mesh_.num_elements(),
      options_.mesh.fluid_elements(), options_.mesh.solid_elements(), mesh_.num_nodes(), size());
}

}  // namespace keller
