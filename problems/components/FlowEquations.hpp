// The fluid part of a flow problem on a fixed mesh, for any of the four fluids: its scene keys,
// its named parameters, the fields it needs (a Newtonian fluid has velocity and pressure only;
// a viscoelastic one adds the interpolated velocity gradient and the conformation, or its
// logarithm), its element and boundary terms, and its boundary conditions on named boundaries
// (FlowBoundaries.hpp: inflows, outflows, walls, driven and moving walls, symmetry lines, given
// tractions). Problems (the rigid channel, the confined cylinder) compose it with their geometry
// and observables.
#pragma once

#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/DirichletTerm.hpp"
#include "core/DofMap.hpp"
#include "core/ElementGeometry.hpp"
#include "core/Mesh.hpp"
#include "core/ParameterSet.hpp"
#include "core/Scene.hpp"
#include "core/SolutionFields.hpp"
#include "core/Status.hpp"
#include "core/Term.hpp"
#include "problems/components/Component.hpp"
#include "problems/components/FlowBoundaries.hpp"
#include "problems/components/FluidOptions.hpp"
#include "problems/kernels/FlowParameters.hpp"
#include "problems/kernels/ViscoelasticFlowKernel.hpp"
#include "problems/laws/ConstitutiveLaw.hpp"
#include "problems/laws/InflowProfile.hpp"

namespace keller {

class FlowEquations final : public Component {
 public:
  // Adds the fluid's parameters (Re; Wi, beta; b for FENE-P) to `params`. iGamma: the index of the
  // velocity scale (mean inflow velocity) in `params`, or -1 for a fixed scale of 1. Throws
  // std::invalid_argument naming the boundary for conditions the mesh cannot carry
  // (FlowBoundaries::validate, InflowFrame::of, axis_normal_components).
  FlowEquations(const Mesh& mesh, const std::string& group, FluidOptions options, FlowBoundaries boundaries,
                ParameterSet& params, int iGamma);
  FlowEquations(const FlowEquations&) = delete;
  FlowEquations& operator=(const FlowEquations&) = delete;

  std::string name() const override { return "fluid"; }
  std::vector<FieldSpec> fields() const override { return fields_; }
  // Creates the terms and adds the Dirichlet conditions. On a moving mesh (a "position" field)
  // the element kernels take their geometry from the node positions of the fluid elements; the
  // inflow and outflow nodes must stay where the mesh has them (the inflow values and the
  // outflow traction use those positions). Where no natural condition fixes the pressure level
  // (no outflow, no traction boundary) the pressure at the centre of the first fluid element is 0.
  void build(const ComponentBuild& build) override;
  const std::vector<std::shared_ptr<const Term>>& terms() const override { return terms_; }

  const FluidOptions& options() const { return options_; }
  // Where the fluid's parameters are in the ParameterSet.
  const FlowParameterIndices& parameter_indices() const { return index_; }
  const std::vector<int>& elements() const { return elements_; }
  const std::vector<std::array<QpGeometry<double>, ref::kQp>>& geometry() const { return geometry_; }
  double velocity_scale() const;
  // A starting state for a straight channel: the first inflow's fully developed profile continued
  // along its flow direction (clamped to its channel across it), and for viscoelastic fluids the
  // matching steady-shear conformation and velocity gradient. Throws std::logic_error if the
  // first inflow is not fully developed.
  void initial_guess(Vector& u) const;
  // A starting state for any geometry: the fluid at rest, the relaxed conformation (the
  // zero-shear steady state, M = I for Oldroyd-B), zero velocity gradient; the problem puts in
  // the Dirichlet values afterwards.
  void rest_state(Vector& u) const;
  // A starting state for any geometry that Newton converges from at higher Wi than from rest or
  // from initial_guess: velocity and pressure of the Stokes flow of a Newtonian fluid of viscosity
  // 1 under the same boundary conditions (StokesStart, one linear solve), the relaxed
  // conformation and zero velocity gradient. Returns that solve's failure, if any.
  Status stokes_state(Vector& u) const;
  // Inflow values at the current parameters, per inflow (FlowBoundaries::inflows order) and
  // node (in boundary_nodes order): velocity, and per mode the conformation unknowns (M or log M
  // components; empty for a Newtonian fluid or a fully developed profile that leaves the domain).
  struct InflowValues {
    std::vector<std::vector<std::array<double, 2>>> velocity;                   // [inflow][node]
    std::vector<std::vector<std::vector<std::array<double, 4>>>> conformation;  // [mode][inflow][node]
  };
  const InflowValues& inflow_values(const ParameterSet& params) const;

  // The polymer modes: one (the field "conformation") unless the scene gives [fluid.modes];
  // a multi-mode fluid's first mode has the field "conformation", mode <name> after it
  // "conformation_<name>". Empty for a Newtonian fluid.
  const std::vector<PolymerMode>& modes() const { return modes_; }
  // The polymer stress sum_k tau_k at a point of element e where the Q1 shape functions are N1,
  // at the parameters p.
  Conformation<double> polymer_stress_at(const Vector& u, const double* p, int e, const double (&N1)[4]) const;

  // Eigenvalues m1 <= m2 <= m3 of each mode's 3x3 conformation tensor at every conformation
  // node (vertices of fluid elements): mode by mode, in node order of `nodes` (which repeats the
  // node list once per mode).
  void conformation_eigenvalues(const Vector& u, std::vector<int>& nodes, std::vector<std::array<double, 3>>& m) const;
  // m1 at every place of min_m1 (the smallest eigenvalue of conformation_eigenvalues, node by node):
  // the values of a problem's min_m1 monitor's places.
  void m1_places(const Vector& u, std::vector<double>& values) const;
  // The gradient in u of m1 at one place of min_m1 (the index of a node in conformation_eigenvalues'
  // order): central differences in that node's own conformation unknowns, the only ones m1 there
  // depends on (step 1e-6 max(1, |u_d|)). Throws std::out_of_range for a place the mesh lacks.
  void m1_place_gradient(const Vector& u, int place, Vector& gradient) const;
  // The extremes over those nodes: the smallest m1 (zero where M loses positive definiteness)
  // and the node where it is, the largest m3 and the largest tr M (FENE-P: < 3b).
  struct ConformationExtremes {
    double min_m1 = INFINITY, max_m3 = -INFINITY, max_trace = -INFINITY;
    int min_m1_node = -1;
  };
  ConformationExtremes conformation_extremes(const Vector& u) const;
  // Extra output fields: the eigenvalues, and M itself in the log formulation.
  void add_fields(const Vector& u, SolutionFields& out) const;

  // The fluid's steady shear viscosity eta(gdot) / eta0 at the parameters p (SteadyFlows.hpp).
  std::function<double(double)> viscosity(const ParameterSet& p) const;

 private:
  // m1 <= m2 <= m3 of mode `mode` at conformation node n.
  std::array<double, 3> node_eigenvalues(const Vector& u, int n, size_t mode) const;
  // The mode's steady shear state (its unknowns: M or log M) at shear rate gdot and the parameters
  // p: steady_state at W = t_k lambda gdot (lambda = Wi / Gamma; Owens: times its Cross factor).
  std::array<double, 4> mode_shear_state(const ParameterSet& p, size_t mode, double gdot,
                                         const LawConstants<double>& law) const;
  template <bool Moving>
  void add_kernels(const DofMap& dofs);
  template <int NC, bool Moving>
  void add_viscoelastic_kernels(const DofMap& dofs, const std::vector<BoundaryEdge>& outflow);
  std::array<double, 4> steady_state(double W, const LawConstants<double>& law) const;

  const Mesh* mesh_;
  std::string group_;
  FluidOptions options_;
  FlowBoundaries boundaries_;
  const ParameterSet* params_;
  FlowParameterIndices index_;
  std::vector<int> elements_;
  std::vector<std::array<QpGeometry<double>, ref::kQp>> geometry_;
  std::vector<FieldSpec> fields_;
  std::vector<PolymerMode> modes_;
  std::vector<std::shared_ptr<const Term>> terms_;
  const DofMap* dofs_ = nullptr;
  struct Inflow {
    InflowFrame frame;      // fully developed only
    InflowProfile profile;  // fully developed only: the channel [frame.lo, frame.hi]
    std::vector<int> nodes;
    std::vector<double> across;  // y' of each node
  };
  std::vector<Inflow> inflows_;
  // a few parameter sets' inflow values (finite-difference probes alternate between two)
  mutable std::vector<std::pair<std::vector<double>, InflowValues>> inflow_cache_;
};

}  // namespace keller
