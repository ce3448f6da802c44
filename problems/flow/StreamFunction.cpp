#include "problems/flow/StreamFunction.hpp"

#include <stdexcept>

namespace keller {

StreamFunction::StreamFunction(const Mesh& mesh, const DofMap& dofs, const std::vector<int>& elements,
                               const std::vector<std::array<QpGeometry<double>, ref::kQp>>& geometry)
    : mesh_(&mesh), dofs_(&dofs), elements_(&elements), geometry_(&geometry) {
  const int n = mesh.num_nodes();
  has_fluid_.assign(static_cast<size_t>(n), 0);
  for (int e : elements)
    for (int a : mesh.element(e)) has_fluid_[static_cast<size_t>(a)] = 1;
  const std::vector<char>& fluid = has_fluid_;
  for (int a = 0; a < n && pin_ < 0; ++a)
    if (fluid[static_cast<size_t>(a)]) pin_ = a;
  if (pin_ < 0) throw std::invalid_argument("stream function: the mesh has no fluid element");
  // the pinned node's row and column, and nodes of no fluid element, are the identity
  std::vector<Eigen::Triplet<double, int>> entries;
  for (int a = 0; a < n; ++a)
    if (a == pin_ || !fluid[static_cast<size_t>(a)]) entries.emplace_back(a, a, 1.0);
  for (size_t k = 0; k < elements.size(); ++k) {
    const std::array<int, 9>& nodes = mesh.element(elements[k]);
    for (const QpGeometry<double>& g : geometry[k])
      for (int i = 0; i < 9; ++i)
        for (int j = 0; j < 9; ++j) {
          const int r = nodes[static_cast<size_t>(i)], c = nodes[static_cast<size_t>(j)];
          if (r == pin_ || c == pin_) continue;
          entries.emplace_back(r, c, g.wdetJ * (g.dN2dx[i][0] * g.dN2dx[j][0] + g.dN2dx[i][1] * g.dN2dx[j][1]));
        }
  }
  SparseMatrix A(n, n);
  A.setFromTriplets(entries.begin(), entries.end());
  ldlt_.compute(A);
  if (ldlt_.info() != Eigen::Success)
    throw std::invalid_argument(
        "stream function: the fluid's elements do not form one connected region (psi has a free constant per part)");
}

Vector StreamFunction::solve(const Vector& u) const {
  const ref::Tables& tb = ref::tables();
  const int fv = dofs_->field_index("velocity");
  Vector b = Vector::Zero(mesh_->num_nodes());
  for (size_t k = 0; k < elements_->size(); ++k) {
    const int e = (*elements_)[k];
    int d[18];
    dofs_->element_dofs(fv, e, d);
    const std::array<int, 9>& nodes = mesh_->element(e);
    for (int q = 0; q < ref::kQp; ++q) {
      const QpGeometry<double>& g = (*geometry_)[k][static_cast<size_t>(q)];
      double vx = 0, vy = 0;
      for (int a = 0; a < 9; ++a) {
        vx += tb.N2[q][a] * u[d[a]];
        vy += tb.N2[q][a] * u[d[9 + a]];
      }
      for (int i = 0; i < 9; ++i)
        b[nodes[static_cast<size_t>(i)]] += g.wdetJ * (g.dN2dx[i][0] * -vy + g.dN2dx[i][1] * vx);
    }
  }
  b[pin_] = 0.0;
  for (int a = 0; a < mesh_->num_nodes(); ++a)
    if (!has_fluid_[static_cast<size_t>(a)]) b[a] = 0.0;
  return ldlt_.solve(b);
}

}  // namespace keller
