#include "problems/flow/FlowProblem.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>

#include "core/GmshMesh.hpp"
#include "problems/components/Composition.hpp"

namespace keller {

namespace {

std::string listed(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "none" : out;
}

Mesh read_mesh(const FlowOptions& o) {
  GmshOptions g;
  g.geo_parameters = o.geo_parameters;
  return read_gmsh_mesh(o.mesh_path, g);
}

// The fluid's region: the scene's, or the mesh's only 2D physical group.
std::string fluid_region(const FlowOptions& o, const Mesh& mesh) {
  if (!o.region.empty()) {
    if (!mesh.has_group(o.region))
      throw std::invalid_argument(fmt::format("mesh.region = \"{}\": the mesh {} has no such region (it has: {})",
                                              o.region, o.mesh_path, listed(mesh.group_names())));
    return o.region;
  }
  if (mesh.group_names().size() != 1)
    throw std::invalid_argument(fmt::format("the mesh {} has {} regions ({}): mesh.region must name the fluid's",
                                            o.mesh_path, mesh.group_names().size(), listed(mesh.group_names())));
  return mesh.group_names().front();
}

// Every boundary of the mesh has a condition, every condition a boundary.
void check_boundaries(const FlowOptions& o, const Mesh& mesh) {
  std::vector<std::string> missing, unknown;
  for (const std::string& b : mesh.boundary_names())
    if (std::find(o.boundary_names.begin(), o.boundary_names.end(), b) == o.boundary_names.end()) missing.push_back(b);
  for (const std::string& b : o.boundary_names)
    if (!mesh.has_boundary(b)) unknown.push_back(b);
  if (missing.empty() && unknown.empty()) return;
  std::string what;
  if (!missing.empty())
    what += fmt::format("the mesh's boundar{} {} ha{} no condition in the scene (add [boundaries.<name>] type = ...)",
                        missing.size() == 1 ? "y" : "ies", listed(missing), missing.size() == 1 ? "s" : "ve");
  if (!unknown.empty())
    what += fmt::format("{}the scene gives a condition on {}, which the mesh does not have", what.empty() ? "" : "; ",
                        listed(unknown));
  throw std::invalid_argument(fmt::format("{} (the mesh {} has: {}; the scene names: {})", what, o.mesh_path,
                                          listed(mesh.boundary_names()), listed(o.boundary_names)));
}

}  // namespace

FlowProblem::FlowProblem(const FlowOptions& options) : FlowProblem(options, read_mesh(options)) {}

FlowProblem::FlowProblem(const FlowOptions& options, Mesh mesh) : options_(options), mesh_(std::move(mesh)) {
  region_ = fluid_region(options_, mesh_);
  check_boundaries(options_, mesh_);
  flow_ = std::make_unique<FlowEquations>(mesh_, region_, options_.fluid, options_.boundaries, params_, -1);
  ComposedSystem system = Composition().add(*flow_).build(mesh_, params_);
  dofs_ = std::move(system.dofs);
  dirichlet_ = system.dirichlet;
  assemble(dofs_->size(), system.terms());
  observables_ = std::make_unique<FlowObservables>(mesh_, *dofs_, *flow_, params_,
                                                   FlowConstraints{dirichlet_->dofs(), options_.boundaries.symmetry},
                                                   options_.observables);
  for (size_t k = 0; k < options_.observables.size(); ++k)
    if (options_.observables[k].monitor) monitor_observables_.push_back(static_cast<int>(k));
}

Vector FlowProblem::initial_guess() {
  // the Stokes flow under the same conditions (one linear solve): Newton starts closer than from rest
  Vector u = Vector::Zero(size());
  if (!flow_->stokes_state(u).is_ok()) {
    u.setZero();
    flow_->rest_state(u);
  }
  for (int k = 0; k < dirichlet_->num_items(); ++k) u[dirichlet_->dofs()[k]] = dirichlet_->value(k);
  return u;
}

std::vector<std::string> FlowProblem::observable_names() const {
  std::vector<std::string> names = observables_->names();
  if (options_.fluid.viscoelastic()) names.insert(names.end(), {"min_m1", "min_m1_x", "min_m1_y", "max_m3"});
  return names;
}

Status FlowProblem::observables(const Vector& u, std::vector<double>& values) {
  Vector R;
  if (observables_->needs_reaction()) {
    const Status st = assembler().weak_residual(u, R);
    if (!st.is_ok()) return st;
  }
  Status st = observables_->evaluate(u, observables_->needs_reaction() ? &R : nullptr, values);
  if (!st.is_ok()) return st;
  if (options_.fluid.viscoelastic()) {
    const FlowEquations::ConformationExtremes x = flow_->conformation_extremes(u);
    const Mesh::Point at = x.min_m1_node >= 0 ? mesh_.node(x.min_m1_node) : Mesh::Point{NAN, NAN};
    values.insert(values.end(), {x.min_m1, at[0], at[1], x.max_m3});
  }
  return {};
}

std::vector<std::string> FlowProblem::monitor_names() const {
  std::vector<std::string> names;
  if (options_.fluid.viscoelastic()) names.push_back("min_m1");
  const std::vector<std::string> all = observables_->names();
  for (int k : monitor_observables_) names.push_back(all[static_cast<size_t>(k)]);
  return names;
}

Status FlowProblem::monitors(const Vector& u, std::vector<double>& values) {
  values.clear();
  if (options_.fluid.viscoelastic()) values.push_back(flow_->conformation_extremes(u).min_m1);
  if (monitor_observables_.empty()) return {};
  std::vector<double> all;
  Vector R;
  if (observables_->needs_reaction()) {
    const Status st = assembler().weak_residual(u, R);
    if (!st.is_ok()) return st;
  }
  const Status st = observables_->evaluate(u, observables_->needs_reaction() ? &R : nullptr, all);
  if (!st.is_ok()) return st;
  for (int k : monitor_observables_) values.push_back(all[static_cast<size_t>(k)]);
  return {};
}

bool FlowProblem::has_observable_gradient(int observable) const {
  // min_m1 follows the scene's observables
  return has_monitor_gradient(0) && observable == static_cast<int>(observables_->names().size());
}

Status FlowProblem::observable_gradient(int observable, const Vector& u, Vector& gradient) {
  if (!has_observable_gradient(observable)) return MonitorGradients::observable_gradient(observable, u, gradient);
  return monitor_gradient(0, u, gradient);
}

Status FlowProblem::monitor_places(int monitor, const Vector& u, std::vector<double>& values) {
  if (!has_places(monitor)) throw std::out_of_range("flow: monitor " + std::to_string(monitor) + " has no places");
  flow_->m1_places(u, values);
  return {};
}

Status FlowProblem::monitor_place_gradient(int monitor, int place, const Vector& u, Vector& gradient) {
  if (!has_places(monitor)) throw std::out_of_range("flow: monitor " + std::to_string(monitor) + " has no places");
  flow_->m1_place_gradient(u, place, gradient);
  return {};
}

std::string FlowProblem::why_no_time_derivative() const {
  if (options_.fluid.viscoelastic() || params_.get("Re") > 0.0) return {};
  return "a Newtonian fluid at parameters.Re = 0 (Stokes flow) has no time derivative (B = 0: no eigenvalue is "
         "finite, nothing evolves); set parameters.Re > 0";
}

SolutionFields FlowProblem::fields(const Vector& u) const {
  SolutionFields f = extract_fields(mesh_, *dofs_, u);
  flow_->add_fields(u, f);
  return f;
}

std::string FlowProblem::summary() const {
  const FluidOptions& f = options_.fluid;
  return fmt::format("flow, {}{}; mesh {}: {} elements, {} nodes; {} unknowns", f.describe(),
                     params_.get("Re") > 0.0 ? ", inertia" : "", options_.mesh_path, mesh_.num_elements(),
                     mesh_.num_nodes(), size());
}

}  // namespace keller
