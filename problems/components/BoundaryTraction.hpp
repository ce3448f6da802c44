// The stress of a fluid on the boundary of its domain, from the discrete state: at the 3 Gauss
// points of a boundary edge, the Cauchy stress sigma = -P I + beta (K + K^T) + tau_p (K the
// velocity gradient of the Q2 velocity, P the P1disc pressure of the edge's element, tau_p the
// polymer stress of the Q1 conformation, or of its logarithm, interpolated to the point, summed
// over a multi-mode fluid's modes: FlowEquations::polymer_stress_at) and the
// traction sigma n on the fluid's outward normal n. Shared by the observables that integrate it
// (the cylinder's surface drag, a flow problem's forces, wall shear stress and mean pressures).
#pragma once

#include <array>

#include "core/DofMap.hpp"
#include "core/Mesh.hpp"
#include "core/ParameterSet.hpp"
#include "core/ReferenceElement.hpp"
#include "core/Types.hpp"
#include "problems/components/FlowEquations.hpp"

namespace keller {

// The fluid's state at one Gauss point of a boundary edge.
struct TractionPoint {
  double x[2] = {0, 0};       // position
  double normal[2] = {0, 0};  // the fluid's outward unit normal
  double wds = 0;             // Gauss weight times the line element
  double velocity[2] = {0, 0};
  double pressure = 0;
  double sxx = 0, sxy = 0, syy = 0;  // the Cauchy stress (solvent, pressure and polymer)
  double traction[2] = {0, 0};       // sigma n: the force per length the outside exerts on the fluid
};

class BoundaryTraction {
 public:
  // The fields of `dofs` (velocity, pressure; the modes' conformations for a viscoelastic
  // fluid) and the fluid's parameters at their indices in the ParameterSet given to evaluate;
  // `flow` (built on `dofs`) outlives this.
  BoundaryTraction(const Mesh& mesh, const DofMap& dofs, const FlowEquations& flow);

  // The 3 Gauss points of boundary edge `be` at state u and the parameters' present values.
  // False when the edge's element is inverted or degenerate (out is then incomplete).
  bool evaluate(const Vector& u, const ParameterSet& params, const BoundaryEdge& be,
                std::array<TractionPoint, ref::kEdgeQp>& out) const;

 private:
  const Mesh* mesh_;
  const DofMap* dofs_;
  const FlowEquations* flow_;
  int fv_ = -1, fp_ = -1;
};

}  // namespace keller
