// Observables of a steady flow on the named boundaries and regions of its mesh, declared by the
// user (a scene's [observables.NAME] tables): forces, flow rates, mean pressures and pressure
// drops, the Couette correction of a contraction, a vortex's length (where the wall shear stress
// changes sign) and intensity (the extremum of the stream function in a region), and the smallest
// conformation eigenvalue and where it is. Each is a functional of the discrete state u at the
// parameters' present values, continuous in u (so that it can be a monitor whose zeros the
// continuation locates), in the model's units (lengths as the mesh has them, eta0 = 1, velocities
// in the inflow's scale). docs/observables.md is the user's page of each definition.
//
// Definitions (Alves, Oliveira & Pinho, JNNFM 110 (2003) 45-75, for the contraction):
// - Force: the force the fluid exerts on the boundary, component x or y, F = -int sigma n ds (n
//   the fluid's outward normal, sigma = -P I + beta (K + K^T) + tau_p). Where the boundary's
//   velocity component is given (every node of it a Dirichlet row: a wall, a moving wall, a given
//   inflow) it is the consistent reaction, minus the sum of the weak momentum residual over those
//   rows (as the cylinder's drag); where a node of the boundary is also a node of a neighbouring
//   boundary whose velocity is given (a wall meeting a given inflow), that neighbour's share of
//   the node's test function is taken out with the neighbour's surface traction, so that the
//   reaction of an exact state is the exact force. Elsewhere (an outflow, a traction boundary)
//   it is the surface integral of the traction, 3-point Gauss per edge.
// - FlowRate: int v . n ds with the fluid's outward normal (positive out of the domain).
// - MeanPressure: int P ds / int ds of the P1disc pressure on the boundary's edges.
// - PressureDrop: mean pressure of `boundary` minus that of `other`.
// - CouetteCorrection: C = (Delta p - Delta p_fd) / (2 tau_w), Delta p the drop of mean pressure
//   from the inflow (`boundary`) to the outflow (`other`); Delta p_fd = G_u L_u + G_d L_d, the
//   fully developed pressure gradients G of the fluid (problems/laws/InflowProfile) in the
//   upstream and downstream channels times their lengths from the inflow and outflow to the
//   contraction plane x = origin[0]; tau_w = G_d H_d, the downstream fully developed wall shear
//   stress. A channel's half-width H is its end boundary's length, halved unless the boundary
//   touches a symmetry line; its mean velocity is |flow rate| / the boundary's length. In fully
//   developed flow of these fluids P is uniform across the channel (tau_yy = 0 in steady shear),
//   so the mean pressure is the wall's and the centreline's there too. Channels run along x.
// - Reattachment: along the wall `boundary` (one chain of edges, `origin` at one of its ends),
//   the wall shear stress (the tangential traction) at the edges' Gauss points, ordered by the
//   arclength from `origin`; the value is the arclength of the sign change met first coming from
//   the far end (where the flow is undisturbed), its zero interpolated linearly between the two
//   Gauss points that bracket it, times `scale`; 0 where the shear stress keeps its sign (no
//   vortex). Gauss points rather than nodes: the traction is single-valued there (at a node two
//   elements give two gradients), and it varies continuously with u, as does the interpolated
//   zero while it stays between two points. From the far end, not from the corner: near a corner
//   the exact flow has an infinite sequence of ever smaller Moffatt eddies, which a fine mesh
//   begins to resolve; the main vortex's reattachment is the sign change farthest from it.
// - StreamFunctionExtremum: psi with v = (dpsi/dy, -dpsi/dx), the Q2 least-squares solution of
//   grad psi = (-v_y, v_x) (problems/flow/StreamFunction), shifted so that its mean over the
//   nodes of `boundary` is 0 (a wall or symmetry line has v . n = 0, so psi is one constant along
//   it, up to the discretisation error); the largest (maximum) or smallest value over the nodes in
//   the box `region`, times `scale`, divided by |the flow rate through `other`| if `other` is set.
// - MinM1: the smallest eigenvalue m1 of the conformation tensor over the conformation nodes
//   (component 0), or the x (1) or y (2) coordinate of the node where it is (viscoelastic only).
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "core/DofMap.hpp"
#include "core/Mesh.hpp"
#include "core/ParameterSet.hpp"
#include "core/Status.hpp"
#include "core/Types.hpp"
#include "problems/components/BoundaryTraction.hpp"
#include "problems/components/FlowEquations.hpp"

namespace keller {

class StreamFunction;

struct FlowObservableSpec {
  enum class Kind {
    Force,
    FlowRate,
    MeanPressure,
    PressureDrop,
    CouetteCorrection,
    Reattachment,
    StreamFunctionExtremum,
    MinM1
  };
  std::string name;  // the observable's name in outputs
  Kind kind = Kind::Force;
  std::string boundary;                    // where it is (PressureDrop: from; Couette: the inflow; Reattachment: the
                                           // wall; StreamFunctionExtremum: where psi = 0; MinM1: unused)
  std::string other;                       // PressureDrop: to; Couette: the outflow; StreamFunctionExtremum: the
                                           // boundary whose |flow rate| divides psi (empty: none)
  int component = 0;                       // Force: 0 x, 1 y; MinM1: 0 the value, 1 its x, 2 its y
  double scale = 1.0;                      // multiplies the value (a half domain's force: 2)
  std::array<double, 2> origin{0.0, 0.0};  // Reattachment: an end of the wall, where lengths start;
                                           // Couette: the contraction plane is x = origin[0]
  std::array<double, 4> region{0.0, 0.0, 0.0, 0.0};  // StreamFunctionExtremum: xmin xmax ymin ymax
  bool maximum = true;                               // StreamFunctionExtremum: the largest psi (false: the smallest)
  bool surface_integral = false;                     // Force: the surface integral even where the reaction is available
  bool monitor = false;  // also a monitor (for the caller: continuation events on its zeros)
};

// "force", "flow-rate", "mean-pressure", "pressure-drop", "couette-correction", "reattachment",
// "stream-function-extremum", "min-m1"; the inverse throws std::invalid_argument listing them.
const char* to_string(FlowObservableSpec::Kind kind);
FlowObservableSpec::Kind flow_observable_kind(const std::string& name);

// What the observables need to know of the boundary conditions.
struct FlowConstraints {
  std::vector<int> given;             // the dofs whose values are given (the Dirichlet term's)
  std::vector<std::string> symmetry;  // the symmetry lines (a channel touching one is its half)
};

class FlowObservables {
 public:
  // Validates every spec against the mesh and the fluid: std::invalid_argument naming the
  // observable, its kind and what to change (a boundary the mesh lacks, a reattachment wall that
  // is not one chain or whose ends are not at origin, a region with no node, min m1 of a
  // Newtonian fluid, its place as a monitor, a repeated name). Keeps references to its
  // arguments but `specs` and `constraints`.
  FlowObservables(const Mesh& mesh, const DofMap& dofs, const FlowEquations& flow, const ParameterSet& params,
                  const FlowConstraints& constraints, std::vector<FlowObservableSpec> specs);
  ~FlowObservables();
  FlowObservables(const FlowObservables&) = delete;
  FlowObservables& operator=(const FlowObservables&) = delete;

  std::vector<std::string> names() const;
  const std::vector<FlowObservableSpec>& specs() const { return specs_; }
  // Whether evaluate needs the weak residual (a force by the reaction).
  bool needs_reaction() const;
  // The values in the order of the specs. weak_residual: the problem's weak residual at u
  // (Assembler::weak_residual), needed where needs_reaction(). A failure (an inverted element,
  // a fully developed flow that cannot be computed) is a Status; values are then incomplete.
  Status evaluate(const Vector& u, const Vector* weak_residual, std::vector<double>& values) const;

 private:
  struct Chain;  // a wall's Gauss points in order from origin
  struct EdgeIntegrals {
    double length = 0, flow_rate = 0, pressure = 0, x = 0;  // int ds, v . n ds, P ds, x ds
  };
  std::unique_ptr<Chain> build_chain(const FlowObservableSpec& s) const;
  Status integrals(const std::string& boundary, const Vector& u, EdgeIntegrals& out) const;
  Status edge_failure(const BoundaryEdge& be) const;
  bool uses_reaction(const FlowObservableSpec& s) const;
  Status force(const FlowObservableSpec& s, const Vector& u, const Vector* R, double& value) const;
  Status couette(const FlowObservableSpec& s, const Vector& u, double& value) const;
  Status reattachment(const FlowObservableSpec& s, const Chain& chain, const Vector& u, double& value) const;
  Status stream_extremum(const FlowObservableSpec& s, const std::vector<int>& region, const Vector& psi,
                         const Vector& u, double& value) const;
  double min_m1(const FlowObservableSpec& s, const Vector& u) const;
  bool given(int dof) const { return dof >= 0 && given_[static_cast<size_t>(dof)] != 0; }
  bool component_given(const std::string& boundary, int c) const;
  bool touches_symmetry(const std::string& boundary) const;

  const Mesh* mesh_;
  const DofMap* dofs_;
  const FlowEquations* flow_;
  const ParameterSet* params_;
  std::vector<FlowObservableSpec> specs_;
  std::vector<char> given_;  // per dof
  std::vector<std::string> symmetry_;
  BoundaryTraction traction_;
  std::vector<std::unique_ptr<Chain>> chains_;  // per spec (Reattachment only)
  std::vector<std::vector<int>> region_nodes_;  // per spec (StreamFunctionExtremum only)
  std::unique_ptr<StreamFunction> stream_;      // where a spec needs it
};

}  // namespace keller
