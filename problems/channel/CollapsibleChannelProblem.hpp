// The collapsible channel of model.md, fully coupled and steady: any of the four fluids in the
// 19 x 1 channel whose top wall, over the deformable section, is the incompressible neo-Hookean
// solid of thickness t under the external pressure Pe. Unknowns: the flow fields on the fluid
// elements, the node positions of fluid and solid ("position": elliptic mesh equations in the
// fluid, solid equilibrium in the solid, shared at the interface), and the solid pressure.
// Coupling (method.md): no slip on the deformed interface (v = 0; in the time-dependent form with
// dynamics.mass_matrix = "moving-wall", v = dx/dt: docs/dynamics.md), and the fluid momentum
// residual of each interface node (the consistent reaction) added to the solid's position row
// of that node, so force balance holds without a boundary derivative of the velocity. The
// fluid kernels take their geometry from the position unknowns: the Jacobian holds the shape
// derivatives. Parameters: Gamma, Re, t, Pe, and Wi, beta (b) for the viscoelastic fluids.
// Observables: dx_max, dy_max (the interface point of largest deflection from (Lu + L/2, 1)),
// gap_min, dP (mean pressure across the mesh lines through the ends of the deformable section),
// Q_in, Q_out, area_change (solid), mesh_quality (smallest det J of the fluid mesh relative to the
// generated mesh; <= 0 is an inverted element), min_detF (solid), and for viscoelastic fluids
// min_m1, max_m3, the position of min_m1 (x_min_m1, y_min_m1) and max_trM (FENE-P: < 3b).
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "core/AssembledProblem.hpp"
#include "core/DirichletTerm.hpp"
#include "core/DofMap.hpp"
#include "core/MonitorGradients.hpp"
#include "core/Quantities.hpp"
#include "core/Scene.hpp"
#include "problems/channel/ChannelMesh.hpp"
#include "problems/components/FlowEquations.hpp"
#include "problems/components/FluidMeshMotion.hpp"
#include "problems/components/SolidWall.hpp"

namespace keller {

struct CollapsibleOptions {
  ChannelGeometry geometry;  // thickness: the starting value of t
  ChannelMeshSpec mesh;
  FluidOptions fluid;
  MeshMotionOptions motion;
  double Gamma = 4.95e-4;
  double Pe = 0.04;
  // The time-dependent form (B of B du/dt = -F). false: the time derivatives of the flow fields at
  // the nodes and no slip (v = 0) on the interface, the wall adjusting quasi-statically without
  // kinematics; true: the physical form, time derivatives at fixed points of space (ALE: the nodal
  // rate minus xdot . grad) and the kinematic condition v = dx/dt on the interface.
  bool moving_wall_dynamics = true;
  // rho_s / rho of the wall and the fluid: > 0 gives the wall inertia (density ratio x Re / Gamma in
  // units of eta0 / G) and the wall velocity as an unknown; 0: the quasi-static wall. Needs the
  // moving-wall form and Re > 0.
  double wall_density_ratio = 0.0;

  static void declare(SceneSchema& schema);
  static CollapsibleOptions from_scene(const Scene& scene);
  // Throws std::invalid_argument (naming the keys) for a combination the problem cannot build.
  void validate() const;
};

class CollapsibleChannelProblem final : public AssembledProblem, public MonitorGradients {
 public:
  explicit CollapsibleChannelProblem(const CollapsibleOptions& options);

  std::string name() const override { return "collapsible-channel"; }
  Vector initial_guess() override;
  double residual_scale() const override;
  // Pe from 0 (no external load: the initial guess is then nearly the solution), then, for a
  // viscoelastic fluid, Wi from 0.01 (the relaxation time near zero).
  std::vector<Homotopy> homotopies() const override;
  std::vector<std::string> observable_names() const override { return observables_.names(); }
  Status observables(const Vector& u, std::vector<double>& values) override;
  // min_m1 for a viscoelastic fluid: zero where M loses positive definiteness.
  std::vector<std::string> monitor_names() const override { return monitors_.names(); }
  Status monitors(const Vector& u, std::vector<double>& values) override;
  // min_m1 over the conformation's vertex nodes: m1 at each of them (FlowEquations::conformation_eigenvalues'
  // order), and its gradient by central differences in that node's conformation unknowns.
  bool has_places(int monitor) const override { return options_.fluid.viscoelastic() && monitor == 0; }
  Status monitor_places(int monitor, const Vector& u, std::vector<double>& values) override;
  Status monitor_place_gradient(int monitor, int place, const Vector& u, Vector& gradient) override;
  // min_m1's gradient (at its place): its zero is located by Newton.
  bool has_monitor_gradient(int monitor) const override { return options_.fluid.viscoelastic() && monitor == 0; }
  // The observable min_m1 is that monitor, with its gradient: a branch that stops on it lands
  // its last step on the zero.
  bool has_observable_gradient(int observable) const override;
  Status observable_gradient(int observable, const Vector& u, Vector& gradient) override;
  SolutionFields fields(const Vector& u) const override;
  std::string summary() const override;

  const Mesh& mesh() const { return mesh_; }
  const DofMap& dofs() const { return *dofs_; }
  const SolidWall& wall() const { return *wall_; }
  const FlowEquations& flow() const { return *flow_; }
  const CollapsibleOptions& options() const { return options_; }
  // One observable by name, computed alone; throws std::invalid_argument for an unknown name.
  double observable(const std::string& name, const Vector& u) const { return observables_.value(name, u); }

  // Flow rate int v . n ds (n towards +x) through every vertical mesh line of the deformed
  // fluid mesh, upstream to downstream.
  std::vector<double> column_flow_rates(const Vector& u) const;
  // Mean fluid pressure along the mesh line through the upstream (end = 0) or downstream
  // (end = 1) end of the deformable section (the one-sided values of the two element columns
  // that meet there averaged).
  double section_pressure(const Vector& u, int end) const;
  // The mean fluid pressure over the inlet (x = 0) minus that over the outlet (x = Lu + L + Ld):
  // the pressure drop of the whole channel, which the reference study plots (dP is that of the
  // deformable section alone).
  double inlet_outlet_pressure_drop(const Vector& u) const;
  // Mean fluid pressure along one side (edge) of a column of elements of block b.
  double line_pressure(const Vector& u, const MeshBlock& b, int column, int edge) const;
  // The force the solid receives from the fluid: the sum of the fluid's weak momentum
  // residuals at the interface nodes that are not clamped, which the coupling adds to the
  // solid's rows; it is -int (sum of their test functions) T n_f ds (n_f: the fluid's outward
  // normal). The clamped corner nodes pass their share to the clamps.
  std::array<double, 2> fluid_force_on_wall(const Vector& u) const;
  // The same force integrated directly, -int w T n_f ds over the deformed interface with
  // w = 1 - (the corner nodes' test functions) and the discrete stress
  // T = -P I + beta (K + K^T) + tau_p(M) at edge Gauss points. It differs from the weak
  // reaction by the discretisation error only.
  std::array<double, 2> interface_traction_integral(const Vector& u) const;
  // Smallest det(dx/ds) of the fluid elements relative to the generated mesh.
  double min_mesh_jacobian(const Vector& u) const { return motion_->min_relative_jacobian(*dofs_, u); }

 private:
  // The fluid's stress at the edge Gauss points of the interface, left to right.
  struct InterfaceSample {
    std::array<double, 2> x, normal;  // position, the fluid's outward unit normal
    double ds = 0;                    // Gauss weight times the line element
    double pressure = 0;
    double extra[2][2] = {{0, 0}, {0, 0}};  // beta (K + K^T) + tau_p
    double Mxx = 0;                         // NaN for a Newtonian fluid
    double free_weight = 1;                 // sum of the test functions of the unclamped nodes
  };
  std::vector<InterfaceSample> interface_samples(const Vector& u) const;
  void declare_quantities();
  void element_positions(const Vector& u, int e, double (&xy)[9][2]) const;
  // The fluid pressure at position x of element e (node positions xy).
  double fluid_pressure(const Vector& u, int e, const double (&xy)[9][2], const double (&x)[2]) const;

  CollapsibleOptions options_;
  Mesh mesh_;
  int iGamma_ = -1;
  std::unique_ptr<FlowEquations> flow_;
  std::unique_ptr<SolidWall> wall_;
  std::unique_ptr<FluidMeshMotion> motion_;
  std::unique_ptr<DofMap> dofs_;
  std::shared_ptr<DirichletTerm> dirichlet_;
  std::vector<int> interface_nodes_;
  mutable Mesh deformed_;
  Quantities observables_, monitors_;
};

}  // namespace keller
