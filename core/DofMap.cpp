#include "core/DofMap.hpp"

#include <algorithm>
#include <stdexcept>

namespace keller {

const char* to_string(Basis b) {
  switch (b) {
    case Basis::Q2: return "Q2";
    case Basis::Q1: return "Q1";
    case Basis::P1Disc: return "P1disc";
  }
  return "?";
}

int basis_size(Basis b) {
  switch (b) {
    case Basis::Q2: return 9;
    case Basis::Q1: return 4;
    case Basis::P1Disc: return 3;
  }
  return 0;
}

DofMap::DofMap(const Mesh& mesh, std::vector<FieldSpec> fields) : mesh_(&mesh), fields_(std::move(fields)) {
  const int ng = static_cast<int>(mesh.group_names().size());
  for (size_t f = 0; f < fields_.size(); ++f) {
    const FieldSpec& fs = fields_[f];
    if (fs.components.empty()) throw std::invalid_argument("field '" + fs.name + "' has no components");
    for (size_t g = 0; g < f; ++g)
      if (fields_[g].name == fs.name) throw std::invalid_argument("field '" + fs.name + "' declared twice");
    std::vector<char> act(ng, fs.groups.empty() ? 1 : 0);
    for (const std::string& gname : fs.groups) act[mesh.group_index(gname)] = 1;
    active_.push_back(act);
    node_dofs_.emplace_back(static_cast<size_t>(mesh.num_nodes()) * fs.components.size(), -1);
    elem_dofs_.emplace_back(static_cast<size_t>(mesh.num_elements()) * 3 * fs.components.size(), -1);
  }
  // Which nodes carry which nodal field.
  std::vector<std::vector<char>> carries(fields_.size(), std::vector<char>(mesh.num_nodes(), 0));
  for (int e = 0; e < mesh.num_elements(); ++e) {
    for (size_t f = 0; f < fields_.size(); ++f) {
      if (!active_[f][mesh.element_group(e)]) continue;
      const auto& el = mesh.element(e);
      if (fields_[f].basis == Basis::Q2)
        for (int a = 0; a < 9; ++a) carries[f][el[a]] = 1;
      else if (fields_[f].basis == Basis::Q1)
        for (int v : ref::q1_node) carries[f][el[v]] = 1;
    }
  }
  int next = 0;
  for (int n = 0; n < mesh.num_nodes(); ++n)
    for (size_t f = 0; f < fields_.size(); ++f)
      if (carries[f][n])
        for (size_t c = 0; c < fields_[f].components.size(); ++c)
          node_dofs_[f][n * fields_[f].components.size() + c] = next++;
  for (int e = 0; e < mesh.num_elements(); ++e)
    for (size_t f = 0; f < fields_.size(); ++f)
      if (fields_[f].basis == Basis::P1Disc && active_[f][mesh.element_group(e)])
        for (int k = 0; k < 3; ++k)
          for (size_t c = 0; c < fields_[f].components.size(); ++c)
            elem_dofs_[f][(e * 3 + k) * fields_[f].components.size() + c] = next++;
  size_ = next;
}

bool DofMap::has_field(const std::string& name) const {
  return std::any_of(fields_.begin(), fields_.end(), [&](const FieldSpec& f) { return f.name == name; });
}

int DofMap::field_index(const std::string& name) const {
  for (size_t f = 0; f < fields_.size(); ++f)
    if (fields_[f].name == name) return static_cast<int>(f);
  throw std::invalid_argument("no field named '" + name + "' in this problem");
}

int DofMap::element_dof(int f, int e, int k, int c) const { return elem_dofs_[f][(e * 3 + k) * num_components(f) + c]; }

void DofMap::element_dofs(int f, int e, int* out) const {
  const int nc = num_components(f);
  const auto& el = mesh_->element(e);
  switch (fields_[f].basis) {
    case Basis::Q2:
      for (int c = 0; c < nc; ++c)
        for (int a = 0; a < 9; ++a) out[c * 9 + a] = node_dof(f, el[a], c);
      break;
    case Basis::Q1:
      for (int c = 0; c < nc; ++c)
        for (int k = 0; k < 4; ++k) out[c * 4 + k] = node_dof(f, el[ref::q1_node[k]], c);
      break;
    case Basis::P1Disc:
      for (int c = 0; c < nc; ++c)
        for (int k = 0; k < 3; ++k) out[c * 3 + k] = element_dof(f, e, k, c);
      break;
  }
}

std::string DofMap::describe(int dof) const {
  for (size_t f = 0; f < fields_.size(); ++f) {
    const int nc = num_components(static_cast<int>(f));
    const auto& nd = node_dofs_[f];
    auto it = std::find(nd.begin(), nd.end(), dof);
    if (it != nd.end()) {
      const int k = static_cast<int>(it - nd.begin());
      return fields_[f].name + "." + fields_[f].components[k % nc] + " at node " + std::to_string(k / nc);
    }
    const auto& ed = elem_dofs_[f];
    it = std::find(ed.begin(), ed.end(), dof);
    if (it != ed.end()) {
      const int k = static_cast<int>(it - ed.begin());
      return fields_[f].name + "." + fields_[f].components[k % nc] + " coefficient " + std::to_string((k / nc) % 3) +
             " of element " + std::to_string(k / nc / 3);
    }
  }
  return "dof " + std::to_string(dof);
}

}  // namespace keller
