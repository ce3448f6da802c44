#include "problems/cylinder/CylinderProblem.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "core/BlockMeshBuilder.hpp"
#include "problems/components/Composition.hpp"

namespace keller {

CylinderMeshSpec CylinderMeshSpec::preset(const std::string& name) {
  static const std::vector<std::pair<std::string, int>> levels = {{"C1", 1}, {"C2", 2}, {"C3", 3}, {"C4", 4}};
  for (const auto& [n, f] : levels) {
    if (n != name) continue;
    CylinderMeshSpec s;
    s.name = name;
    s.n_quarter = 8 * f;
    s.n_radial = 8 * f;
    s.nx_upstream = 12 * f;
    s.nx_downstream = 24 * f;
    return s;
  }
  throw std::invalid_argument("unknown cylinder mesh '" + name + "' (C1, C2, C3, C4)");
}

void CylinderOptions::declare(SceneSchema& s) {
  s.section("geometry", "cylinder of radius 1 centred in a channel of half-width 2 (lengths in R)");
  s.real("geometry.upstream_length", 20.0, "distance from the inflow to the cylinder's centre", Range::above(2.0));
  s.real("geometry.downstream_length", 30.0, "distance from the cylinder's centre to the outflow", Range::above(2.0));
  s.section("mesh", "named meshes C1..C4 (refinement 1..4 of C1) or explicit sizes");
  s.string("mesh.name", "C1", "mesh preset; 'custom' takes the sizes below", {"C1", "C2", "C3", "C4", "custom"});
  s.integer("mesh.n_quarter", 0, "custom: elements along a quarter of the cylinder", Range::at_least(0));
  s.integer("mesh.n_radial", 0, "custom: elements from the cylinder to the box around it", Range::at_least(0));
  s.integer("mesh.nx_upstream", 0, "custom: elements along the upstream channel", Range::at_least(0));
  s.integer("mesh.nx_downstream", 0, "custom: elements along the downstream channel", Range::at_least(0));
  s.real("mesh.radial_ratio", 4.0, "largest / smallest radial element (fine at the cylinder)", Range::at_least(1));
  s.real("mesh.upstream_ratio", 10.0, "largest / smallest upstream element (fine near the cylinder)",
         Range::at_least(1));
  s.real("mesh.downstream_ratio", 20.0, "largest / smallest downstream element (fine in the near wake)",
         Range::at_least(1));
  FluidOptions::declare(s, 0.59, 0.1);
}

CylinderOptions CylinderOptions::from_scene(const Scene& sc) {
  CylinderOptions o;
  o.upstream_length = sc.real("geometry.upstream_length");
  o.downstream_length = sc.real("geometry.downstream_length");
  const std::string name = sc.string("mesh.name");
  const char* sizes[] = {"mesh.n_quarter", "mesh.n_radial", "mesh.nx_upstream", "mesh.nx_downstream"};
  if (name == "custom") {
    for (const char* k : sizes)
      if (sc.integer(k) < 1) throw sc.error(k, "a custom mesh needs every size >= 1");
    o.mesh.name = "custom";
    o.mesh.n_quarter = static_cast<int>(sc.integer("mesh.n_quarter"));
    o.mesh.n_radial = static_cast<int>(sc.integer("mesh.n_radial"));
    o.mesh.nx_upstream = static_cast<int>(sc.integer("mesh.nx_upstream"));
    o.mesh.nx_downstream = static_cast<int>(sc.integer("mesh.nx_downstream"));
  } else {
    for (const char* k : sizes)
      if (sc.differs_from_default(k))
        throw sc.error(k, "explicit sizes need mesh.name = \"custom\" (got \"" + name + "\")");
    o.mesh = CylinderMeshSpec::preset(name);
  }
  o.mesh.radial_ratio = sc.real("mesh.radial_ratio");
  o.mesh.upstream_ratio = sc.real("mesh.upstream_ratio");
  o.mesh.downstream_ratio = sc.real("mesh.downstream_ratio");
  o.fluid = FluidOptions::from_scene(sc);
  return o;
}

Mesh build_cylinder_mesh(const CylinderOptions& o) {
  const CylinderMeshSpec& s = o.mesh;
  const double Lu = o.upstream_length, Ld = o.downstream_length;
  auto arc = [](double theta) { return Mesh::Point{std::cos(theta), std::sin(theta)}; };
  // transfinite blend between the arc (t = 0) and a straight side of the box (t = 1)
  auto blend = [](const Mesh::Point& a, const Mesh::Point& b, double t) {
    return Mesh::Point{(1 - t) * a[0] + t * b[0], (1 - t) * a[1] + t * b[1]};
  };
  const Grading radial = Grading::start(s.radial_ratio), around = Grading::uniform();
  BlockMeshBuilder b;
  const int up = b.add_block({"upstream", "fluid", s.nx_upstream, s.n_quarter, Grading::end(s.upstream_ratio), around,
                              [=](double u, double v) { return Mesh::Point{-Lu + (Lu - 2.0) * u, 2.0 * v}; },
                              {"symmetry", "", "wall", "inflow"}});
  const int west = b.add_block({"west", "fluid", s.n_quarter, s.n_radial, around, radial,
                                [=](double u, double t) { return blend(arc(M_PI - 0.25 * M_PI * u), {-2.0, 2.0 * u}, t); },
                                {"cylinder", "", "", "symmetry"}});
  const int north = b.add_block({"north", "fluid", 2 * s.n_quarter, s.n_radial, around, radial,
                                 [=](double u, double t) {
                                   return blend(arc(0.75 * M_PI - 0.5 * M_PI * u), {-2.0 + 4.0 * u, 2.0}, t);
                                 },
                                 {"cylinder", "", "wall", ""}});
  // east runs radially in s and around in t (so that it is positively oriented and its outer
  // side x = 2 runs upwards like the downstream block's inflow side)
  const int east = b.add_block({"east", "fluid", s.n_radial, s.n_quarter, radial, around,
                                [=](double r, double v) { return blend(arc(0.25 * M_PI * v), {2.0, 2.0 * v}, r); },
                                {"symmetry", "", "", "cylinder"}});
  const int down = b.add_block({"downstream", "fluid", s.nx_downstream, s.n_quarter, Grading::start(s.downstream_ratio),
                                around, [=](double u, double v) { return Mesh::Point{2.0 + (Ld - 2.0) * u, 2.0 * v}; },
                                {"symmetry", "outflow", "wall", ""}});
  b.connect(up, Side::Right, west, Side::Top);
  b.connect(west, Side::Right, north, Side::Left);
  b.connect(north, Side::Right, east, Side::Top);
  b.connect(east, Side::Right, down, Side::Left);
  return b.build();
}

CylinderProblem::CylinderProblem(const CylinderOptions& options)
    : options_(options), mesh_(build_cylinder_mesh(options)) {
  FlowBoundaries bc;
  bc.walls = {"wall", "cylinder"};
  bc.symmetry = {"symmetry"};
  bc.channel_lo = -2.0;
  bc.channel_hi = 2.0;
  flow_ = std::make_unique<FlowEquations>(mesh_, "fluid", options_.fluid, bc, params_, -1);
  ComposedSystem system = Composition().add(*flow_).build(mesh_, params_);
  dofs_ = std::move(system.dofs);
  dirichlet_ = system.dirichlet;
  assembler_ = std::make_unique<Assembler>(dofs_->size(), system.terms());
  const int fv = dofs_->field_index("velocity");
  for (int n : mesh_.boundary_nodes("cylinder")) cylinder_vx_.push_back(dofs_->node_dof(fv, n, 0));
}

Vector CylinderProblem::initial_guess() {
  Vector u = Vector::Zero(size());
  flow_->initial_guess(u);
  for (int k = 0; k < dirichlet_->num_items(); ++k) u[dirichlet_->dofs()[k]] = dirichlet_->value(k);
  return u;
}

double CylinderProblem::drag(const Vector& u) const {
  Vector R;
  const Status st = assembler_->weak_residual(u, R);
  if (!st.is_ok()) return NAN;
  // sum of the weak residual over the cylinder's nodes = int T n_out ds (n_out into the
  // cylinder) = minus the force on it; both halves
  double f = 0;
  for (int d : cylinder_vx_) f -= R[d];
  return 2.0 * f;
}

std::vector<std::string> CylinderProblem::observable_names() const {
  std::vector<std::string> names = {"K"};
  if (options_.fluid.viscoelastic()) names.insert(names.end(), {"min_m1", "max_m3"});
  return names;
}

Status CylinderProblem::observables(const Vector& u, std::vector<double>& values) {
  values = {drag(u)};
  if (options_.fluid.viscoelastic()) {
    std::vector<int> nodes;
    std::vector<std::array<double, 3>> eig;
    flow_->conformation_eigenvalues(u, nodes, eig);
    double m1 = INFINITY, m3 = -INFINITY;
    for (const auto& e : eig) {
      m1 = std::min(m1, e[0]);
      m3 = std::max(m3, e[2]);
    }
    values.push_back(m1);
    values.push_back(m3);
  }
  return {};
}

std::vector<std::string> CylinderProblem::monitor_names() const {
  if (options_.fluid.viscoelastic()) return {"min_m1"};
  return {};
}

Status CylinderProblem::monitors(const Vector& u, std::vector<double>& values) {
  values.clear();
  if (!options_.fluid.viscoelastic()) return {};
  std::vector<double> obs;
  Status st = observables(u, obs);
  if (st.is_ok()) values = {obs[1]};
  return st;
}

SolutionFields CylinderProblem::fields(const Vector& u) const {
  SolutionFields f = extract_fields(mesh_, *dofs_, u);
  flow_->add_fields(u, f);
  return f;
}

std::string CylinderProblem::summary() const {
  const FluidOptions& f = options_.fluid;
  return fmt::format("confined cylinder (blockage 0.5), {} fluid{}; mesh {}: {} elements, {} nodes; {} unknowns",
                     to_string(f.model), f.viscoelastic() && f.log_conformation ? " (log-conformation)" : "",
                     options_.mesh.name, mesh_.num_elements(), mesh_.num_nodes(), size());
}

}  // namespace keller
