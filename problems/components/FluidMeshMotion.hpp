// The moving fluid mesh of the collapsible channel as a component: the node positions of the
// fluid elements are unknowns ("position" field) governed by the elliptic mesh equations
// (EllipticMeshKernel), with the boundary rows of method.md: on the rigid walls the normal row
// becomes y = y_wall and the tangential row keeps its natural condition (nodes slide, mesh lines
// meet the wall orthogonally) or fixes x (an option); the inflow and outflow nodes stay where
// the generated mesh has them (method.md lets them slide along the ends; fixing them keeps the
// inflow profile a function of the parameters alone, and the ends are 7 widths away from the
// wall); nodes owned by other equations (the interface, which the solid moves) are left alone.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/DirichletTerm.hpp"
#include "core/DofMap.hpp"
#include "core/Mesh.hpp"
#include "core/ParameterSet.hpp"
#include "core/Scene.hpp"
#include "core/Term.hpp"
#include "core/Types.hpp"
#include "problems/components/Component.hpp"

namespace keller {

struct MeshMotionOptions {
  bool sliding_walls = true;  // wall nodes slide along the rigid walls (false: fixed)

  static void declare(SceneSchema& schema);
  static MeshMotionOptions from_scene(const Scene& scene);
};

struct MeshMotionBoundaries {
  std::vector<std::string> walls = {"bottom_wall", "top_wall"};  // horizontal rigid walls
  std::vector<std::string> ends = {"inflow", "outflow"};         // vertical ends
};

class FluidMeshMotion final : public Component {
 public:
  // mesh: the generated mesh (its positions define the spacing weights and the wall lines).
  FluidMeshMotion(const Mesh& mesh, const std::string& group, MeshMotionOptions options,
                  MeshMotionBoundaries boundaries = {});

  std::string name() const override { return "fluid mesh motion"; }
  // None of its own: it governs the shared "position" field on the fluid elements.
  std::vector<FieldSpec> fields() const override { return {}; }
  // The elliptic mesh equations and the wall rows, on every fluid node whose position row the
  // components built before do not own (build.owned_position_nodes: the interface, moved by the solid).
  void build(const ComponentBuild& build) override;
  const std::vector<std::shared_ptr<const Term>>& terms() const override { return terms_; }
  const std::vector<int>& elements() const { return elements_; }
  // Writes the generated positions into the position dofs of the fluid nodes.
  void generated_state(const DofMap& dofs, Vector& u) const;
  // Smallest det(dx/ds) over the Gauss points of the fluid elements at state u, relative to its
  // value on the generated mesh (<= 0: an inverted element).
  double min_relative_jacobian(const DofMap& dofs, const Vector& u) const;

 private:
  const Mesh* mesh_;
  MeshMotionOptions options_;
  MeshMotionBoundaries boundaries_;
  std::vector<int> elements_;
  std::vector<std::shared_ptr<const Term>> terms_;
};

}  // namespace keller
