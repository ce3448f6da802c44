// A problem's system composed of components (Component.hpp) and the fields they share: the
// fields in the order they are added, one DofMap, one Dirichlet term, every component built in
// the order it was added (each told which nodes' position rows the ones before it own), and the
// terms for the assembler. The problem keeps what is its own: couplings between components
// (reaction redirects), its observables and its starting state.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/DirichletTerm.hpp"
#include "core/DofMap.hpp"
#include "core/Mesh.hpp"
#include "core/ParameterSet.hpp"
#include "core/Term.hpp"
#include "problems/components/Component.hpp"

namespace keller {

struct ComposedSystem {
  std::unique_ptr<DofMap> dofs;
  std::shared_ptr<DirichletTerm> dirichlet;
  std::vector<std::shared_ptr<const Term>> component_terms;  // in the order of the components

  // The assembler's terms: the components', then `extra` (the problem's own), then the Dirichlet term.
  std::vector<std::shared_ptr<const Term>> terms(const std::vector<std::shared_ptr<const Term>>& extra = {}) const;
};

class Composition {
 public:
  // The component's fields are added at this point of the field order; it is built in this order.
  Composition& add(Component& component);
  // A field no single component owns (the node positions a solid and a fluid mesh share).
  Composition& share(FieldSpec field);
  // dirichlet_name: the name of the Dirichlet term in diagnostics.
  ComposedSystem build(const Mesh& mesh, const ParameterSet& params,
                       const std::string& dirichlet_name = "dirichlet") const;

 private:
  std::vector<Component*> components_;
  std::vector<FieldSpec> fields_;
};

}  // namespace keller
