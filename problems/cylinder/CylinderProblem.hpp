// The confined-cylinder benchmark of viscoelastic flow: a cylinder of radius R = 1 centred in a
// channel of half-width 2 (blockage 0.5), creeping flow, mean velocity U = 1, eta0 = 1, so
// Wi = lambda U / R and the drag coefficient K = F_x / (eta0 U) per unit length. By symmetry
// only the upper half is meshed (v_y = 0 on the axis). The mesh is mapped multi-block: three
// blocks around the cylinder with isoparametric curved edges on it (transfinite blending of the
// arc and the enclosing box), graded radially, and graded channel blocks upstream and
// downstream. The drag is the consistent reaction: the weak momentum residual summed over the
// cylinder's nodes (twice, for both halves); the surface integral of the traction and the DEVSS
// term's share of the reaction are observables beside it, as checks.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/AssembledProblem.hpp"
#include "core/DirichletTerm.hpp"
#include "core/DofMap.hpp"
#include "core/Scene.hpp"
#include "problems/components/FlowEquations.hpp"

namespace keller {

struct CylinderMeshSpec {
  std::string name = "C1";
  int n_quarter = 8;               // elements along a quarter of the cylinder (the N block has twice as many)
  int n_radial = 8;                // elements from the cylinder to the enclosing box
  int nx_upstream = 12;            // elements along the upstream channel
  int nx_downstream = 24;          // elements along the downstream channel
  double radial_ratio = 4.0;       // largest / smallest radial size (fine at the cylinder)
  double upstream_ratio = 10.0;    // largest / smallest (fine next to the box)
  double downstream_ratio = 20.0;  // largest / smallest (fine next to the box: the wake)
  double wake_ratio = 1.0;         // across the channel behind the cylinder (the east block around, the
                                   // downstream block in y): largest / smallest, fine on the axis
  int n_rear = 0;                  // elements around the rear eighth and across the downstream channel (0: n_quarter)
  double rear_ratio = 1.0;         // around the rear eighth of the cylinder, fine at the rear stagnation point
  // C1..C4 (refinement 1..4 of C1), W1..W4 (the same sizes, the wake resolved)
  static CylinderMeshSpec preset(const std::string& name);
  // Elements of the five blocks (upstream, west, north, east, downstream).
  long elements() const {
    const long q = n_quarter, r = n_radial, w = n_rear > 0 ? n_rear : n_quarter;
    return nx_upstream * q + q * r + 2 * q * r + r * w + nx_downstream * w;
  }
};

struct CylinderOptions {
  double upstream_length = 20.0;    // from the inflow to the cylinder's centre
  double downstream_length = 30.0;  // from the cylinder's centre to the outflow
  CylinderMeshSpec mesh;
  FluidOptions fluid;

  static void declare(SceneSchema& schema);
  static CylinderOptions from_scene(const Scene& scene);
};

// Blocks upstream, west, north, east, downstream; boundaries inflow, outflow, wall (y = 2),
// symmetry (y = 0), cylinder.
Mesh build_cylinder_mesh(const CylinderOptions& options);

class CylinderProblem final : public AssembledProblem {
 public:
  explicit CylinderProblem(const CylinderOptions& options);

  std::string name() const override { return "cylinder"; }
  Vector initial_guess() override;
  std::vector<std::string> observable_names() const override;
  Status observables(const Vector& u, std::vector<double>& values) override;
  std::vector<std::string> monitor_names() const override;
  Status monitors(const Vector& u, std::vector<double>& values) override;
  SolutionFields fields(const Vector& u) const override;
  std::string summary() const override;

  // Drag coefficient K = F_x / (eta0 U) of the whole cylinder: the weak reaction.
  double drag(const Vector& u) const;
  // The same drag by other functionals of the discrete solution, which agree with the reaction
  // only as the mesh converges: surface, the traction -P n + beta (K + K^T) n + tau_p n
  // integrated over the cylinder (3-point Gauss per edge); devss, the DEVSS term's share of the
  // reaction, beta_a int grad(phi) : ((K + K^T) - (L + L^T)) with phi = 1 on the cylinder (0 for
  // a Newtonian fluid).
  struct DragTerms {
    double reaction = 0, surface = 0, devss = 0;
  };
  DragTerms drag_terms(const Vector& u) const;
  const Mesh& mesh() const { return mesh_; }
  const DofMap& dofs() const { return *dofs_; }
  const FlowEquations& flow() const { return *flow_; }

 private:
  CylinderOptions options_;
  Mesh mesh_;
  std::unique_ptr<FlowEquations> flow_;
  std::unique_ptr<DofMap> dofs_;
  std::shared_ptr<DirichletTerm> dirichlet_;
  std::vector<int> cylinder_vx_;        // x-velocity rows of the cylinder's nodes
  std::vector<int> cylinder_elements_;  // elements with a node on the cylinder
  std::vector<char> on_cylinder_;       // per mesh node
};

}  // namespace keller
