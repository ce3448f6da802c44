// Boundary kernel of a given constant traction t = T n on a boundary. The momentum equation in
// divergence form has the boundary term - int phi . (T n) ds; with T n = t given it becomes the
// load - int phi_a t_i ds on the momentum rows of the element owning each edge. It does not
// depend on the unknowns (its Jacobian is zero) nor on the parameters.
//
// Local unknowns: v_x (9), v_y (9) of the element owning the edge (the rows).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/DofMap.hpp"
#include "core/ElementGeometry.hpp"
#include "core/Mesh.hpp"
#include "core/Status.hpp"

namespace keller {

class TractionKernel {
 public:
  static constexpr int kSize = 18;

  TractionKernel(const Mesh& mesh, const DofMap& dofs, const std::vector<BoundaryEdge>& edges,
                 std::array<double, 2> traction)
      : edges_(edges), traction_(traction) {
    const int fv = dofs.field_index("velocity");
    dofs_.resize(edges_.size() * kSize);
    geometry_.resize(edges_.size());
    for (size_t k = 0; k < edges_.size(); ++k) {
      dofs.element_dofs(fv, edges_[k].element, &dofs_[k * kSize]);
      double xy[9][2];
      mesh.element_nodes(edges_[k].element, xy);
      map_edge(xy, edges_[k].edge, geometry_[k]);
    }
  }

  std::string name() const { return "traction"; }
  int num_items() const { return static_cast<int>(edges_.size()); }
  void item_dofs(int item, int* out) const { std::copy_n(&dofs_[static_cast<size_t>(item) * kSize], kSize, out); }

  template <class T, class P>
  Status evaluate(int item, const T*, const P*, T* r) const {
    const ref::Tables& tb = ref::tables();
    const int e = edges_[static_cast<size_t>(item)].edge;
    for (int i = 0; i < kSize; ++i) r[i] = 0.0;
    for (int q = 0; q < ref::kEdgeQp; ++q) {
      const EdgeQpGeometry<double>& g = geometry_[static_cast<size_t>(item)][q];
      for (int a = 0; a < 9; ++a) {
        const double N = tb.edge_N2[e][q][a] * g.wds;
        r[a] -= N * traction_[0];
        r[9 + a] -= N * traction_[1];
      }
    }
    return {};
  }

 private:
  std::vector<BoundaryEdge> edges_;
  std::array<double, 2> traction_;
  std::vector<int> dofs_;
  std::vector<std::array<EdgeQpGeometry<double>, ref::kEdgeQp>> geometry_;
};

}  // namespace keller
