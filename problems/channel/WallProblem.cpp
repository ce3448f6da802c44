#include "problems/channel/WallProblem.hpp"

#include <fmt/format.h>

#include <cmath>

#include "core/KernelTerm.hpp"
#include "problems/components/Composition.hpp"
#include "problems/kernels/FollowerPressureKernel.hpp"

namespace keller {

void WallOptions::declare(SceneSchema& s) {
  declare_channel_mesh_keys(s);
  s.section("parameters", "continuation parameters and their starting values");
  s.real("parameters.t", 0.4, "wall thickness t (units of W)",
         Range::between(SolidWall::min_thickness, SolidWall::max_thickness));
  s.real("parameters.Pe", 0.04, "external pressure on the top of the wall (units of G)");
  s.real("parameters.Pin", 0.0, "uniform pressure on the bottom of the wall (units of G)");
  s.section("dynamics", "the time-dependent form B du/dt = -F (stability, keller evolve): docs/dynamics.md");
  s.real("dynamics.inertia", 0.0,
         "the wall's density rho_s W^2 G / eta0^2: > 0 gives it inertia (the wall velocity an unknown); 0: "
         "quasi-static, no time-dependent form",
         Range::non_negative());
}

WallOptions WallOptions::from_scene(const Scene& scene) {
  WallOptions o;
  o.geometry = channel_geometry_from(scene);
  o.geometry.thickness = scene.real("parameters.t");
  o.mesh = channel_mesh_spec_from(scene);
  o.Pe = scene.real("parameters.Pe");
  o.Pin = scene.real("parameters.Pin");
  o.inertia = scene.real("dynamics.inertia");
  return o;
}

WallProblem::WallProblem(const WallOptions& options)
    : options_(options), mesh_(build_wall_mesh(options.geometry, options.mesh)) {
  const ChannelGeometry& g = options_.geometry;
  wall_ =
      std::make_unique<SolidWall>(mesh_, WallGeometry{g.upstream_length, g.upstream_length + g.deformable_length, 1.0},
                                  g.thickness, options_.Pe, params_);
  iPin_ = params_.add("Pin", options_.Pin, "uniform pressure on the bottom of the wall (units of G)");
  if (options_.inertia > 0) {
    const double rho = options_.inertia;
    wall_->set_inertia([rho](const ParameterSet&) { return rho; });
  }
  ComposedSystem system =
      Composition().share({"position", Basis::Q2, {"x", "y"}, {"solid"}}).add(*wall_).build(mesh_, params_, "clamps");
  dofs_ = std::move(system.dofs);
  dirichlet_ = system.dirichlet;
  // the uniform pressure Pin standing in for the fluid, on the bottom face
  const auto pin = std::make_shared<KernelTerm<FollowerPressureKernel>>(
      FollowerPressureKernel(mesh_, *dofs_, mesh_.boundary("interface"), iPin_), params_);
  // with inertia: rho* dw/dt in the equilibrium rows and w = dx/dt; without, no time-dependent form
  assemble(dofs_->size(), system.terms({pin}), {}, wall_->has_inertia() ? TimeForm::Assembled : TimeForm::None);
  deformed_ = mesh_;
  observables_.add("dx_max", [this](const Vector& u) { return wall_->max_deflection(u)[0]; });
  observables_.add("dy_max", [this](const Vector& u) { return wall_->max_deflection(u)[1]; });
  observables_.add("area_change", [this](const Vector& u) { return wall_->area(u) - wall_->reference_area(); });
  observables_.add("min_detF", [this](const Vector& u) { return wall_->min_jacobian(u); });
}

Vector WallProblem::initial_guess() {
  // the undeformed wall; pi = 0 balances no load
  Vector u = Vector::Zero(size());
  wall_->reference_state(u);
  return u;
}

Status WallProblem::observables(const Vector& u, std::vector<double>& values) {
  observables_.evaluate(u, values);
  return {};
}

SolutionFields WallProblem::fields(const Vector& u) const {
  // written on the deformed configuration, with the displacement as a field
  const int fx = dofs_->field_index("position");
  for (int n = 0; n < mesh_.num_nodes(); ++n)
    deformed_.set_node(n, {u[dofs_->node_dof(fx, n, 0)], u[dofs_->node_dof(fx, n, 1)]});
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
  return fmt::format(
      "neo-Hookean wall alone (plane strain, incompressible, Q2-P1disc); mesh {}: {} elements, {} nodes; "
      "{} unknowns",
      options_.mesh.name, mesh_.num_elements(), mesh_.num_nodes(), size());
}

}  // namespace keller
