// The stream function of a planar velocity field on a mesh of 9-node elements: psi with
// v = (dpsi/dy, -dpsi/dx), the Q2 least-squares solution of grad psi = (-v_y, v_x), i.e. the
// Neumann problem int grad(phi) . grad(psi) = int grad(phi) . (-v_y, v_x) for every Q2 phi, with
// psi pinned to 0 at one node (psi is defined up to a constant; a caller shifts it). Where the
// velocity is the curl of a Q2 field (on affine elements) that field is recovered to rounding.
// The matrix depends on the mesh alone: it is assembled and factorised once, and each velocity
// field costs one assembly of the right-hand side and one solve.
#pragma once

#include <Eigen/SparseCholesky>
#include <array>
#include <vector>

#include "core/DofMap.hpp"
#include "core/ElementGeometry.hpp"
#include "core/Mesh.hpp"
#include "core/Types.hpp"

namespace keller {

class StreamFunction {
 public:
  // elements: the fluid's elements, geometry: their Gauss points (FlowEquations::geometry()).
  // Throws std::invalid_argument if the matrix cannot be factorised (elements that share no node
  // with the rest: psi has one free constant per part).
  StreamFunction(const Mesh& mesh, const DofMap& dofs, const std::vector<int>& elements,
                 const std::vector<std::array<QpGeometry<double>, ref::kQp>>& geometry);
  // psi at every mesh node (0 at nodes of no fluid element) for the velocity in u.
  Vector solve(const Vector& u) const;

 private:
  const Mesh* mesh_;
  const DofMap* dofs_;
  const std::vector<int>* elements_;
  const std::vector<std::array<QpGeometry<double>, ref::kQp>>* geometry_;
  std::vector<char> has_fluid_;  // per node: of a fluid element
  int pin_ = -1;
  Eigen::SimplicialLDLT<SparseMatrix> ldlt_;
};

}  // namespace keller
