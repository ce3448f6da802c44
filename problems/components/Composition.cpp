#include "problems/components/Composition.hpp"

#include <algorithm>
#include <iterator>

namespace keller {

std::vector<std::shared_ptr<const Term>> ComposedSystem::terms(
    const std::vector<std::shared_ptr<const Term>>& extra) const {
  std::vector<std::shared_ptr<const Term>> all = component_terms;
  all.insert(all.end(), extra.begin(), extra.end());
  all.push_back(dirichlet);
  return all;
}

Composition& Composition::add(Component& component) {
  components_.push_back(&component);
  for (FieldSpec& f : component.fields()) fields_.push_back(std::move(f));
  return *this;
}

Composition& Composition::share(FieldSpec field) {
  fields_.push_back(std::move(field));
  return *this;
}

ComposedSystem Composition::build(const Mesh& mesh, const ParameterSet& params,
                                  const std::string& dirichlet_name) const {
  ComposedSystem s;
  s.dofs = std::make_unique<DofMap>(mesh, fields_);
  s.dirichlet = std::make_shared<DirichletTerm>(dirichlet_name, params);
  ComponentBuild b{*s.dofs, *s.dirichlet, params, s.dofs->has_field("position"), {}};
  for (Component* c : components_) {
    c->build(b);
    for (const auto& t : c->terms()) s.component_terms.push_back(t);
    std::vector<int> owned = c->position_nodes(), merged;
    std::sort(owned.begin(), owned.end());
    std::set_union(b.owned_position_nodes.begin(), b.owned_position_nodes.end(), owned.begin(), owned.end(),
                   std::back_inserter(merged));
    b.owned_position_nodes = std::move(merged);
  }
  return s;
}

}  // namespace keller
