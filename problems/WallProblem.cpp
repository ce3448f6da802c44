#include "problems/WallProblem.hpp"

#include <fmt/format.h>

#include <cmath>

#include "core/KernelTerm.hpp"
#include "problems/FollowerPressureKernel.hpp"

namespace keller {

void WallOptions::declare(SceneSchema& s) {
  declare_channel_mesh_keys(s);
  s.section("parameters", "continuation parameters and their starting values");
  s.real("parameters.t", 0.4, "wall thickness t (units of W)", Range::between(SolidWall::min_thickness, SolidWall::max_thickness));
  s.real("parameters.Pe", 0.04, "external pressure on the top of the wall (units of G)");
  s.real("parameters.Pin", 0.0, "uniform pressure on the bottom of the wall (units of G)");
}

WallOptions WallOptions::from_scene(const Scene& scene) {
  WallOptions o;
  o.geometry = channel_geometry_from(scene);
  o.geometry.thickness = scene.real("parameters.t");
  o.mesh = channel_mesh_spec_from(scene);
  o.Pe = scene.real("parameters.Pe");
  o.Pin = scene.real("parameters.Pin");
  return o;
}

WallProblem::WallProblem(const WallOptions& options)
    : options_(options), mesh_(build_wall_mesh(options.geometry, options.mesh)) {
  const ChannelGeometry& g = options_.geometry;
  wall_ = std::make_unique<SolidWall>(mesh_, WallGeometry{g.upstream_length, g.upstream_length + g.deformable_length, 1.0},
                                      g.thickness, options_.Pe, params_);
  iPin_ = params_.add("Pin", options_.Pin, "uniform pressure on the bottom of the wall (units of G)");
  dofs_ = std::make_unique<DofMap>(
      mesh_, std::vector<FieldSpec>{{"position", Basis::Q2, {"x", "y"}, {"solid"}}, SolidWall::pressure_field()});
  dirichlet_ = std::make_shared<DirichletTerm>("clamps", params_);
  wall_->build(*dofs_, *dirichlet_);
  std::vector<std::shared_ptr<const Term>> terms = wall_->terms();
  terms.push_back(std::make_shared<KernelTerm<FollowerPressureKernel>>(
      FollowerPressureKernel(mesh_, *dofs_, mesh_.boundary("interface"), iPin_), params_));
  terms.push_back(dirichlet_);
  assembler_ = std::make_unique<Assembler>(dofs_->size(), terms);
  deformed_ = mesh_;
}

Vector WallProblem::initial_guess() {
  // the undeformed wall; pi = 0 balances no load
  Vector u = Vector::Zero(size());
  wall_->reference_state(u);
  return u;
}

std::vector<std::string> WallProblem::observable_names() const {
  return {"dx_max", "dy_max", "area_change", "min_detF"};
}

Status WallProblem::observables(const Vector& u, std::vector<double>& values) {
  const auto d = wall_->max_deflection(u);
  values = {d[0], d[1], wall_->area(u) - wall_->reference_area(), wall_->min_jacobian(u)};
  return {};
}

SolutionFields WallProblem::fields(const Vector& u) const {
  // written on the deformed configuration, with the displacement as a field
  const int fx = dofs_->field_index("position");
  for (int n = 0; n < mesh_.num_nodes(); ++n) deformed_.set_node(n, {u[dofs_->node_dof(fx, n, 0)], u[dofs_->node_dof(fx, n, 1)]});
  SolutionFields f = extract_fields(deformed_, *dofs_, u);
  NodalField disp{"displacement", "Q2", {"dx", "dy"}, {"solid"}, Eigen::MatrixXd(mesh_.num_nodes(), 2)};
  for (int n = 0; n < mesh_.num_nodes(); ++n) {
    const auto X = wall_->reference().at(n, params_.values());
    disp.values(n, 0) = deformed_.node(n)[0] - X[0];
    disp.values(n, 1) = deformed_.node(n)[1] - X[1];
  }
  f.nodal.push_back(std::move(disp));
  return f;
}

std::string WallProblem::summary() const {
  return fmt::format("neo-Hookean wall alone (plane strain, incompressible, Q2-P1disc); mesh {}: {} elements, {} nodes; "
                     "{} unknowns",
                     options_.mesh.name, mesh_.num_elements(), mesh_.num_nodes(), size());
}

}  // namespace keller
