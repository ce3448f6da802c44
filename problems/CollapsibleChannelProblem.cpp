#include "problems/CollapsibleChannelProblem.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "core/ElementGeometry.hpp"

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
  return o;
}

CollapsibleChannelProblem::CollapsibleChannelProblem(const CollapsibleOptions& options)
    : options_(options), mesh_(build_channel_mesh(options.geometry, options.mesh, true)) {
  const ChannelGeometry& g = options_.geometry;
  iGamma_ = params_.add("Gamma", options_.Gamma, "wall elasticity parameter (the mean inflow velocity)", Range::positive());
  FlowBoundaries bc;
  bc.walls = {"bottom_wall", "top_wall", "interface"};
  flow_ = std::make_unique<FlowEquations>(mesh_, "fluid", options_.fluid, bc, params_, iGamma_);
  wall_ = std::make_unique<SolidWall>(
      mesh_, WallGeometry{g.upstream_length, g.upstream_length + g.deformable_length, 1.0}, g.thickness, options_.Pe,
      params_);
  motion_ = std::make_unique<FluidMeshMotion>(mesh_, "fluid", options_.motion);

  std::vector<FieldSpec> fields = flow_->fields();
  fields.push_back({"position", Basis::Q2, {"x", "y"}, {"fluid", "solid"}});
  fields.push_back(SolidWall::pressure_field());
  dofs_ = std::make_unique<DofMap>(mesh_, fields);
  dirichlet_ = std::make_shared<DirichletTerm>("dirichlet", params_);
  flow_->build(*dofs_, *dirichlet_, true);
  wall_->build(*dofs_, *dirichlet_);
  std::set<int> solid_nodes;
  for (int e : wall_->elements())
    for (int n : mesh_.element(e)) solid_nodes.insert(n);
  motion_->build(*dofs_, *dirichlet_, std::vector<int>(solid_nodes.begin(), solid_nodes.end()), params_);

  // the fluid's reaction at each interface node goes to the solid's row of that node
  interface_nodes_ = wall_->interface_nodes();
  const int fv = dofs_->field_index("velocity"), fx = dofs_->field_index("position");
  std::vector<std::pair<int, int>> redirects;
  for (int n : interface_nodes_)
    for (int c = 0; c < 2; ++c) {
      const int to = dofs_->node_dof(fx, n, c);
      if (!dirichlet_->constrains(to)) redirects.emplace_back(dofs_->node_dof(fv, n, c), to);
    }
  std::vector<std::shared_ptr<const Term>> terms = flow_->terms();
  for (const auto& t : wall_->terms()) terms.push_back(t);
  for (const auto& t : motion_->terms()) terms.push_back(t);
  terms.push_back(dirichlet_);
  assembler_ = std::make_unique<Assembler>(dofs_->size(), terms, redirects);
  deformed_ = mesh_;
}

double CollapsibleChannelProblem::residual_scale() const { return params_.value(iGamma_); }

std::vector<Problem::Homotopy> CollapsibleChannelProblem::homotopies() const {
  std::vector<Homotopy> h{{"Pe", 0.0}};
  if (params_.has("Wi")) h.push_back({"Wi", 0.01});
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
  for (int e : wall_->elements()) u[dofs_->element_dof(fp, e, 0, 0)] = 1.0 + params_.value(wall_->external_pressure_index());
  for (int k = 0; k < dirichlet_->num_items(); ++k) u[dirichlet_->dofs()[k]] = dirichlet_->value(k);
  return u;
}

void CollapsibleChannelProblem::element_positions(const Vector& u, int e, double (&xy)[9][2]) const {
  const int fx = dofs_->field_index("position");
  const auto& el = mesh_.element(e);
  for (int a = 0; a < 9; ++a)
    for (int i = 0; i < 2; ++i) xy[a][i] = u[dofs_->node_dof(fx, el[a], i)];
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

double CollapsibleChannelProblem::section_pressure(const Vector& u, int end) const {
  const int fp = dofs_->field_index("pressure");
  const MeshBlock& def = mesh_.block("deformable");
  const MeshBlock& other = mesh_.block(end == 0 ? "upstream" : "downstream");
  // (block, column, edge) of the two element columns meeting at the line
  const std::array<std::tuple<const MeshBlock*, int, int>, 2> sides = {
      end == 0 ? std::make_tuple(&other, other.nx - 1, 1) : std::make_tuple(&def, def.nx - 1, 1),
      end == 0 ? std::make_tuple(&def, 0, 3) : std::make_tuple(&other, 0, 3)};
  double mean = 0;
  for (const auto& [b, i, edge] : sides) {
    double pint = 0, len = 0;
    for (int j = 0; j < b->ny; ++j) {
      const int e = b->element(i, j);
      double xy[9][2];
      element_positions(u, e, xy);
      std::array<EdgeQpGeometry<double>, ref::kEdgeQp> eg;
      if (!map_edge(xy, edge, eg)) return std::numeric_limits<double>::quiet_NaN();
      for (const auto& g : eg) {
        const double p = u[dofs_->element_dof(fp, e, 0, 0)] + u[dofs_->element_dof(fp, e, 1, 0)] * (g.x[0] - xy[4][0]) +
                         u[dofs_->element_dof(fp, e, 2, 0)] * (g.x[1] - xy[4][1]);
        pint += p * g.wds;
        len += g.wds;
      }
    }
    mean += 0.5 * pint / len;
  }
  return mean;
}

std::array<double, 2> CollapsibleChannelProblem::fluid_force_on_wall(const Vector& u) const {
  Vector F;
  if (!assembler_->weak_residual(u, F).is_ok()) return {NAN, NAN};
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
  const double beta = ve ? ps.get("beta") : 1.0;
  const double modulus = ve ? (1.0 - beta) * ps.value(iGamma_) / ps.get("Wi") : 0.0;
  const int fv = dofs_->field_index("velocity"), fp = dofs_->field_index("pressure");
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
    for (int k = 0; k < ref::kEdgeQp; ++k) {
      const EdgeQpGeometry<double>& g = eg[k];
      InterfaceSample smp;
      smp.x = {g.x[0], g.x[1]};
      smp.normal = {g.normal[0], g.normal[1]};
      smp.ds = g.wds;
      double K[2][2] = {{0, 0}, {0, 0}};
      for (int a = 0; a < 9; ++a)
        for (int j = 0; j < 2; ++j) {
          K[0][j] += g.dN2dx[a][j] * u[vd[a]];
          K[1][j] += g.dN2dx[a][j] * u[vd[9 + a]];
        }
      smp.pressure = u[dofs_->element_dof(fp, e, 0, 0)] + u[dofs_->element_dof(fp, e, 1, 0)] * (g.x[0] - xy[4][0]) +
                     u[dofs_->element_dof(fp, e, 2, 0)] * (g.x[1] - xy[4][1]);
      for (int r = 0; r < 2; ++r)
        for (int c = 0; c < 2; ++c) smp.extra[r][c] = beta * (K[r][c] + K[c][r]);
      smp.Mxx = std::numeric_limits<double>::quiet_NaN();
      if (ve) {
        double m[4] = {0, 0, 0, 0};
        for (int c = 0; c < nc; ++c)
          for (int q = 0; q < 4; ++q) m[c] += tb.edge_N1[edge][k][q] * u[md[4 * c + q]];
        const Conformation<double> M =
            nc == 4 ? conformation_of<4>(m, fo.log_conformation) : conformation_of<3>(m, fo.log_conformation);
        const double f = fo.model == FluidModel::FeneP ? peterlin(fo.model, nc == 4, M, ps.get("b")) : 1.0;
        const Conformation<double> tp = polymer_stress(M, f, modulus);
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

std::vector<std::string> CollapsibleChannelProblem::observable_names() const {
  std::vector<std::string> names = {"dx_max", "dy_max", "gap_min", "dP", "Q_in", "Q_out", "area_change",
                                    "mesh_quality", "min_detF"};
  if (options_.fluid.viscoelastic()) names.insert(names.end(), {"min_m1", "max_m3", "x_min_m1", "y_min_m1", "max_trM"});
  return names;
}

std::vector<std::string> CollapsibleChannelProblem::monitor_names() const {
  if (options_.fluid.viscoelastic()) return {"min_m1"};  // zero where M loses positive definiteness
  return {};
}

Status CollapsibleChannelProblem::monitors(const Vector& u, std::vector<double>& values) {
  values.clear();
  if (!options_.fluid.viscoelastic()) return {};
  std::vector<double> obs;
  Status st = observables(u, obs);
  if (st.is_ok()) values = {obs[9]};  // min_m1, after the nine observables every fluid has
  return st;
}

Status CollapsibleChannelProblem::observables(const Vector& u, std::vector<double>& values) {
  const auto d = wall_->max_deflection(u);
  double gap = INFINITY;
  for (const auto& p : wall_->interface_shape(u)) gap = std::min(gap, p[1]);
  const std::vector<double> q = column_flow_rates(u);
  values = {d[0], d[1], gap, section_pressure(u, 0) - section_pressure(u, 1), q.front(), q.back(),
            wall_->area(u) - wall_->reference_area(), min_mesh_jacobian(u), wall_->min_jacobian(u)};
  if (options_.fluid.viscoelastic()) {
    std::vector<int> nodes;
    std::vector<std::array<double, 3>> eig;
    flow_->conformation_eigenvalues(u, nodes, eig);
    double m1 = INFINITY, m3 = -INFINITY, tr = -INFINITY;
    int at = -1;
    for (size_t k = 0; k < eig.size(); ++k) {
      if (eig[k][0] < m1) {
        m1 = eig[k][0];
        at = nodes[k];
      }
      m3 = std::max(m3, eig[k][2]);
      tr = std::max(tr, eig[k][0] + eig[k][1] + eig[k][2]);
    }
    const int fx = dofs_->field_index("position");
    values.insert(values.end(), {m1, m3, u[dofs_->node_dof(fx, at, 0)], u[dofs_->node_dof(fx, at, 1)], tr});
  }
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
    for (int i = 0; i < 2; ++i) disp.values(n, i) = deformed_.node(n)[static_cast<size_t>(i)] - mesh_.node(n)[static_cast<size_t>(i)];
  f.nodal.push_back(std::move(disp));
  const auto shape = wall_->interface_shape(u);
  NamedArray iface{"interface_shape", "deformed interface (bottom of the wall), left to right",
                   Eigen::MatrixXd(static_cast<long>(shape.size()), 2), {"x", "y"}};
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
    if (u[dofs_->node_dof(fx, def.node(i, 2 * def.ny), 1)] < u[dofs_->node_dof(fx, def.node(col, 2 * def.ny), 1)]) col = i;
  const bool ve = options_.fluid.viscoelastic();
  const int fv = dofs_->field_index("velocity");
  NamedArray gap{"gap_profile", "across the narrowest gap (the mesh line through the lowest interface node), bottom to top",
                 Eigen::MatrixXd(2 * def.ny + 1, 5), {"x", "y", "vx", "vy", "Mxx"}};
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
  NamedArray flow{"column_flow_rates", "flow rate through every vertical mesh line, upstream to downstream",
                  Eigen::MatrixXd(static_cast<long>(q.size()), 1), {"Q"}};
  for (size_t k = 0; k < q.size(); ++k) flow.values(static_cast<long>(k), 0) = q[k];
  f.arrays.push_back(std::move(flow));
  return f;
}

std::string CollapsibleChannelProblem::summary() const {
  const FluidOptions& f = options_.fluid;
  return fmt::format(
      "collapsible channel, {} fluid{}, neo-Hookean wall, elliptic mesh ({} wall nodes); mesh {}: {} elements ({} fluid + "
      "{} solid), {} nodes; {} unknowns",
      to_string(f.model), f.viscoelastic() && f.log_conformation ? " (log-conformation)" : "",
      options_.motion.sliding_walls ? "sliding" : "fixed", options_.mesh.name, mesh_.num_elements(),
      options_.mesh.fluid_elements(), options_.mesh.solid_elements(), mesh_.num_nodes(), size());
}

}  // namespace keller
