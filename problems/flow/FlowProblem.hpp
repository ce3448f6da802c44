// Steady flow in any 2D geometry: a Gmsh mesh of 9-node quadrilaterals (core/GmshMesh), any keller
// fluid and formulation on its fluid region (problems/components/FlowEquations), the condition the
// scene gives each named boundary (docs/boundaries.md) and the observables it declares
// (problems/flow/FlowObservables, docs/observables.md). The velocity scale is 1: each fully
// developed inflow has its own mean velocity. Before anything is built, the mesh's boundaries and
// the scene's are checked against each other: a boundary without a condition, or a condition on a
// boundary the mesh lacks, is an error naming both lists.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/AssembledProblem.hpp"
#include "core/DirichletTerm.hpp"
#include "core/DofMap.hpp"
#include "core/Mesh.hpp"
#include "core/MonitorGradients.hpp"
#include "problems/components/FlowEquations.hpp"
#include "problems/flow/FlowObservables.hpp"
#include "problems/flow/FlowOptions.hpp"

namespace keller {

class FlowProblem final : public AssembledProblem, public MonitorGradients {
 public:
  // Reads (or meshes) the options' mesh. Throws MeshFileError for an unusable mesh,
  // std::invalid_argument for conditions or observables that do not fit it.
  explicit FlowProblem(const FlowOptions& options);
  // On a given mesh (tests, a mesh built in code).
  FlowProblem(const FlowOptions& options, Mesh mesh);

  std::string name() const override { return "flow"; }
  Vector initial_guess() override;
  std::vector<std::string> observable_names() const override;
  Status observables(const Vector& u, std::vector<double>& values) override;
  // min_m1 for a viscoelastic fluid, then the observables the scene marks as monitors.
  std::vector<std::string> monitor_names() const override;
  Status monitors(const Vector& u, std::vector<double>& values) override;
  // min_m1 (monitor 0 of a viscoelastic fluid) is a minimum over the conformation's nodes: m1 at
  // each (FlowEquations::conformation_eigenvalues' order), its gradient at one of them by central
  // differences in that node's own unknowns, so an event curve follows the node where the minimum
  // sits and locates its switches, and Newton locates the zero of min_m1 (a Wi branch lands on it).
  bool has_places(int monitor) const override { return has_monitor_gradient(monitor); }
  Status monitor_places(int monitor, const Vector& u, std::vector<double>& values) override;
  Status monitor_place_gradient(int monitor, int place, const Vector& u, Vector& gradient) override;
  bool has_monitor_gradient(int monitor) const override { return options_.fluid.viscoelastic() && monitor == 0; }
  // The observable min_m1 is that monitor, with its gradient (a branch that stops on it lands its
  // last step on the zero).
  bool has_observable_gradient(int observable) const override;
  Status observable_gradient(int observable, const Vector& u, Vector& gradient) override;
  // A Newtonian fluid at Re = 0 (Stokes flow) has no time derivative: B = 0.
  std::string why_no_time_derivative() const override;
  SolutionFields fields(const Vector& u) const override;
  std::string summary() const override;

  const Mesh& mesh() const { return mesh_; }
  const DofMap& dofs() const { return *dofs_; }
  const FlowEquations& flow() const { return *flow_; }

 private:
  FlowOptions options_;
  Mesh mesh_;
  std::string region_;
  std::unique_ptr<FlowEquations> flow_;
  std::unique_ptr<DofMap> dofs_;
  std::shared_ptr<DirichletTerm> dirichlet_;
  std::unique_ptr<FlowObservables> observables_;
  std::vector<int> monitor_observables_;  // indices into the observables' values
};

}  // namespace keller
