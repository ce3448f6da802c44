// The boundary conditions of a flow (FlowEquations), each on named mesh boundaries, and the
// geometry they need: the frame of a fully developed inflow (its flow direction and the channel
// its profile spans) and the velocity component an axis-aligned boundary constrains. keller's
// velocity unknowns are the Cartesian v_x, v_y (no rotated unknowns at boundary nodes), so a
// condition on one velocity component (symmetry, fully developed outflow) needs a boundary along
// x or y. docs/boundaries.md describes each condition.
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

#include "core/Mesh.hpp"

namespace keller {

// Flow into the domain. Fully developed: the profile of [inflow] profile across a single straight
// segment, along its inward normal, with the local steady-shear conformation rotated into the
// segment's frame. Given: the uniform `velocity`, and for a viscoelastic fluid the relaxed
// conformation (the steady state at zero shear: M = I for Oldroyd-B).
struct InflowCondition {
  std::string boundary;
  bool fully_developed = true;
  std::array<double, 2> velocity{0, 0};  // given: the velocity (v_x, v_y), times the velocity scale
  // Fully developed: the mean velocity across the channel, times the velocity scale. Negative: the
  // profile leaves the domain (an imposed fully developed outflow; no conformation is imposed).
  double mean_velocity = 1.0;
};

// Flow out of the domain; both fix the pressure level through the natural condition.
struct OutflowCondition {
  std::string boundary;
  // true: tangential velocity 0 and, for a viscoelastic fluid, the polymer traction added
  // (OutflowTractionKernel), so that P = 0 in fully developed flow; the boundary must run along x
  // or y. false: traction free, T n = 0 (the natural condition).
  bool fully_developed = true;
};

// No slip on a rigid wall moving tangentially (a lid, a belt): v = velocity times the velocity
// scale. At a node shared with a no-slip wall the no-slip wall wins.
struct DrivenWall {
  std::string boundary;
  std::array<double, 2> velocity{0, 0};
};

// A given constant traction T n = traction (the total stress, pressure included).
struct TractionCondition {
  std::string boundary;
  std::array<double, 2> traction{0, 0};
};

struct FlowBoundaries {
  std::vector<InflowCondition> inflows;
  std::vector<OutflowCondition> outflows;
  std::vector<std::string> walls;  // no slip, v = 0
  // No slip on walls that move with the mesh (on a moving mesh): the time-dependent form's
  // kinematic condition v = dx/dt (core/RateConstraintTerm), v = 0 at steady states; nodes also on a
  // wall above keep v = 0.
  std::vector<std::string> moving_walls;
  // v . n = 0, tangential traction free; each edge must run along x or y.
  std::vector<std::string> symmetry;
  std::vector<DrivenWall> driven_walls;
  std::vector<TractionCondition> tractions;

  // Every boundary named, in the order above.
  std::vector<std::string> names() const;
  // Whether a natural condition fixes the pressure level (an outflow or a traction boundary);
  // otherwise every boundary has a given normal velocity and the pressure is defined up to a constant.
  bool pressure_level_fixed() const { return !outflows.empty() || !tractions.empty(); }
  // Throws std::invalid_argument naming the boundary: one named twice, one the mesh lacks, a
  // fully developed inflow with a zero or non-finite mean velocity.
  void validate(const Mesh& mesh) const;
};

// The frame of a fully developed inflow on a single straight boundary segment: the flow runs
// along the inward normal e1 = (c, s), the profile across e2 = (-s, c), the coordinate across
// being y' = x . e2 (y itself for an inflow facing +x). The channel [lo, hi] in y' is the segment,
// or, where one end lies on a symmetry boundary, the segment mirrored about that end.
struct InflowFrame {
  std::array<double, 2> normal{1.0, 0.0};  // e1, inward
  double lo = 0.0, hi = 1.0;

  double across(const Mesh::Point& x) const { return identity() ? x[1] : -normal[1] * x[0] + normal[0] * x[1]; }
  bool identity() const { return normal[0] == 1.0 && normal[1] == 0.0; }
  // A symmetric tensor (xx, xy, yy; further entries unchanged) from the local frame to x, y:
  // M' = R M R^T with R = [e1 e2]; unchanged for an inflow facing +x.
  std::array<double, 4> rotate(const std::array<double, 4>& m) const;
  // The velocity gradient (Lxx, Lxy, Lyx, Lyy) of the local shear du'/dy' = g, in x, y.
  std::array<double, 4> shear_gradient(double g) const;

  // Throws std::invalid_argument naming the boundary if it is not a single straight segment, or
  // both its ends lie on symmetry boundaries.
  static InflowFrame of(const Mesh& mesh, const std::string& boundary, const std::vector<std::string>& symmetry);
};

// For each node of a boundary whose every edge runs along x or y: the index of the velocity
// component normal to it (0 on an edge along y, 1 on an edge along x; a node where both meet is
// listed with both). Throws std::invalid_argument naming the boundary and `what` (the condition)
// for an edge along neither.
std::map<int, std::vector<int>> axis_normal_components(const Mesh& mesh, const std::string& boundary,
                                                       const std::string& what);

}  // namespace keller
