// The interface of a problem's physical parts (the fluid's equations, the solid wall, the
// moving fluid mesh): each is constructed on the mesh (adding its named parameters), declares
// the fields it owns, is built once the DofMap exists (its terms and its Dirichlet conditions)
// and then hands its terms to the assembler. A problem composes them with a Composition.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/DirichletTerm.hpp"
#include "core/DofMap.hpp"
#include "core/ParameterSet.hpp"
#include "core/Term.hpp"

namespace keller {

// What a component sees when it is built.
struct ComponentBuild {
  const DofMap& dofs;
  DirichletTerm& dirichlet;
  const ParameterSet& params;
  // The system has a "position" field: node positions are unknowns and the geometry follows them.
  bool moving_mesh = false;
  // Sorted nodes whose position rows belong to the equations of the components built before.
  std::vector<int> owned_position_nodes;
};

class Component {
 public:
  virtual ~Component() = default;

  virtual std::string name() const = 0;
  // The fields this component owns (a field several components share, like the node positions,
  // is declared by the composition instead).
  virtual std::vector<FieldSpec> fields() const = 0;
  // Creates the terms and adds the Dirichlet conditions.
  virtual void build(const ComponentBuild& build) = 0;
  virtual const std::vector<std::shared_ptr<const Term>>& terms() const = 0;
  // Nodes whose position rows this component's equations own, in any order; none by default.
  virtual std::vector<int> position_nodes() const { return {}; }
};

}  // namespace keller
