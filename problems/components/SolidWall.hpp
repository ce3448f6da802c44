// The deformable wall of the collapsible channel as a component: an incompressible neo-Hookean
// block (element group "solid") clamped on its left and right sides, loaded by the follower
// external pressure Pe on its top face, with a reference shape that is a smooth (affine)
// function of the thickness t. It owns the parameters t and Pe, the solid's terms and clamps,
// and what a user reads off the wall (interface shape, maximum deflection, area). Problems
// compose it with a position field that spans the solid (and, coupled, the fluid mesh).
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <vector>

#include "core/AffineReference.hpp"
#include "core/DirichletTerm.hpp"
#include "core/DofMap.hpp"
#include "core/Mesh.hpp"
#include "core/ParameterSet.hpp"
#include "core/Term.hpp"
#include "core/Types.hpp"
#include "problems/components/Component.hpp"

namespace keller {

struct WallGeometry {
  double x_left = 7.0, x_right = 12.0;  // Lu, Lu + L
  double y_bottom = 1.0;                // the reference interface
};

class SolidWall final : public Component {
 public:
  // Admissible wall thickness (units of W), the range of the parameter t and of its scene key.
  static constexpr double min_thickness = 1e-3, max_thickness = 10.0;

  // mesh: holds group "solid" and boundaries interface, wall_top, wall_left, wall_right, built
  // with thickness t0. Adds parameters "t" (wall thickness, 0 < t) and "Pe" to params.
  SolidWall(const Mesh& mesh, WallGeometry geometry, double t0, double Pe, ParameterSet& params);
  SolidWall(const SolidWall&) = delete;
  SolidWall& operator=(const SolidWall&) = delete;

  std::string name() const override { return "solid wall"; }
  // Wall inertia in the time-dependent form, its density rho* (a function of the parameters, in
  // the problem's units): the wall velocity w becomes an unknown (a field of its own, rows w =
  // dx/dt) and rho* dw/dt enters the equilibrium rows (SolidInertiaTerm). Before build(); without
  // it the solid is quasi-static and has no w.
  void set_inertia(std::function<double(const ParameterSet&)> density) { density_ = std::move(density); }
  bool has_inertia() const { return static_cast<bool>(density_); }
  // The solid's fields besides the shared "position": the P1-discontinuous pressure pi, and the
  // wall velocity (Q2) where the wall has inertia.
  std::vector<FieldSpec> fields() const override;
  // Solid element and follower-load terms, and the clamps (x = X(t) on wall_left, wall_right).
  void build(const ComponentBuild& build) override;
  const std::vector<std::shared_ptr<const Term>>& terms() const override { return terms_; }
  // The nodes of the solid elements: their position rows are the solid's equilibrium.
  std::vector<int> position_nodes() const override;

  int thickness_index() const { return it_; }
  int external_pressure_index() const { return iPe_; }
  const AffineReference& reference() const { return reference_; }
  const std::vector<int>& elements() const { return elements_; }
  // Reference positions at the current t, written into the position dofs of solid nodes.
  void reference_state(Vector& u) const;

  // Deformed area of the solid, int J dA0 (exact for Q2 maps), and its reference area L t.
  double area(const Vector& u) const;
  double reference_area() const;
  // Interface (bottom face) nodes from left to right and their deformed positions.
  const std::vector<int>& interface_nodes() const { return interface_nodes_; }
  std::vector<std::array<double, 2>> interface_shape(const Vector& u) const;
  // The interface point of largest vertical deflection |y - 1|, relative to the centre of the
  // flat interface (x_c, 1): (dx_max, dy_max), dy_max < 0 for a collapse, (0, 0) while flat;
  // taken at the nodes and refined by the parabola through the node and its neighbours.
  std::array<double, 2> max_deflection(const Vector& u) const;
  // Smallest det F over the solid's Gauss points (<= 0: an element is inverted).
  double min_jacobian(const Vector& u) const;

 private:
  const Mesh* mesh_;
  WallGeometry geometry_;
  const ParameterSet* params_;
  int it_ = -1, iPe_ = -1;
  AffineReference reference_;
  std::vector<int> elements_;
  std::vector<int> interface_nodes_;
  const DofMap* dofs_ = nullptr;
  std::function<double(const ParameterSet&)> density_;
  std::vector<std::shared_ptr<const Term>> terms_;
};

}  // namespace keller
