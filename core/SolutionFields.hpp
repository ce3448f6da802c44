// What a problem hands to the output writers for one solution: named fields on its mesh
// (nodal values, NaN where a field does not live; discontinuous per-element coefficients),
// and plain named arrays for problems or profiles without a 2D mesh (1D grids, interface
// shapes). Writers (SolutionWriter) know nothing about the physics.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/DofMap.hpp"
#include "core/Mesh.hpp"
#include "core/Types.hpp"

namespace keller {

struct NodalField {
  std::string name;
  std::string basis;  // "Q2", "Q1" (Q1 values are given at vertex nodes and
                      // interpolated to the others, which is exact)
  std::vector<std::string> components;
  std::vector<std::string> groups;  // element groups it lives on (empty = all)
  Eigen::MatrixXd values;           // num_nodes x components, NaN where absent
};

struct ElementField {
  std::string name;
  std::string basis;  // "P1disc": value = c0 + c1 (x - xc) + c2 (y - yc)
  std::vector<std::string> components;
  std::vector<std::string> groups;
  Eigen::MatrixXd coefficients;   // num_elements x (3 * components), component-major
  Eigen::MatrixXd centre_values;  // num_elements x components (c0), for cell plots
};

struct NamedArray {
  std::string name;
  std::string doc;
  Eigen::MatrixXd values;  // rows x columns
  std::vector<std::string> columns;
};

struct SolutionFields {
  const Mesh* mesh = nullptr;
  std::vector<NodalField> nodal;
  std::vector<ElementField> element;
  std::vector<NamedArray> arrays;
};

// All fields of a DofMap extracted from a solution vector.
SolutionFields extract_fields(const Mesh& mesh, const DofMap& dofs, const Vector& u);

}  // namespace keller
