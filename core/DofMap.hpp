// Degree-of-freedom map built from the list of active fields only: a field that a scene does
// not switch on has no unknowns at all. Nodal fields (Q2 on all nodes, Q1 on vertex nodes) and
// discontinuous fields (P1 in physical coordinates, 3 coefficients per element) live on the
// elements of chosen groups. Numbering is node by node (all nodal fields of a node together),
// then element by element, which keeps the unknowns of an element close together.
#pragma once

#include <string>
#include <vector>

#include "core/Mesh.hpp"

namespace keller {

enum class Basis { Q2, Q1, P1Disc };
const char* to_string(Basis b);
// Number of element-local basis functions: 9, 4 or 3.
int basis_size(Basis b);

struct FieldSpec {
  std::string name;  // e.g. "velocity"
  Basis basis = Basis::Q2;
  std::vector<std::string> components;  // e.g. {"vx", "vy"}; size = number of components
  std::vector<std::string> groups;      // element groups it lives on; empty = all
};

class DofMap {
 public:
  DofMap(const Mesh& mesh, std::vector<FieldSpec> fields);

  int size() const { return size_; }
  int num_fields() const { return static_cast<int>(fields_.size()); }
  const FieldSpec& field(int f) const { return fields_[f]; }
  bool has_field(const std::string& name) const;
  int field_index(const std::string& name) const;  // throws std::invalid_argument if absent
  int num_components(int f) const { return static_cast<int>(fields_[f].components.size()); }
  // Whether field f lives on element e.
  bool on_element(int f, int e) const { return active_[f][mesh_group(e)] != 0; }

  // Global dof of a nodal field at mesh node `node`, component c; -1 if the field has no dof there.
  int node_dof(int f, int node, int c) const { return node_dofs_[f][node * num_components(f) + c]; }
  // Global dof of coefficient k, component c, of a discontinuous field on element e; -1 if absent.
  int element_dof(int f, int e, int k, int c) const;
  // Element-local dofs of field f on element e, component-major: c * basis_size + a.
  // Writes basis_size * components entries; entries are -1 where the field is absent.
  void element_dofs(int f, int e, int* out) const;
  int element_dofs_size(int f) const { return basis_size(fields_[f].basis) * num_components(f); }

  // Human-readable name of a global dof, e.g. "velocity.vy at node 17" (for error messages).
  std::string describe(int dof) const;
  const Mesh& mesh() const { return *mesh_; }

 private:
  int mesh_group(int e) const { return mesh_->element_group(e); }
  const Mesh* mesh_;
  std::vector<FieldSpec> fields_;
  std::vector<std::vector<char>> active_;    // [field][group]
  std::vector<std::vector<int>> node_dofs_;  // [field][node * comps + c]
  std::vector<std::vector<int>> elem_dofs_;  // [field][(e * 3 + k) * comps + c]
  int size_ = 0;
};

}  // namespace keller
