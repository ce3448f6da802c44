// Follower pressure p on boundary edges, acting on the deformed surface: the traction is
// -p n with n the outward normal of the deformed edge, so the residual of the position rows
// gains + p int phi_a n ds. n ds is polynomial in the edge's node positions (the rotated
// tangent), so the term is exact and smooth even for a strongly curved edge.
//
// Local unknowns (6): x of the edge's 3 nodes, then their y.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include "core/DofMap.hpp"
#include "core/Mesh.hpp"
#include "core/ReferenceElement.hpp"
#include "core/Status.hpp"

namespace keller {

class FollowerPressureKernel {
 public:
  static constexpr int kSize = 6;

  // pressure: index of the parameter p (e.g. Pe); sign: +1 for a pressure pushing on the
  // surface from outside (traction -p n), -1 for one pulling.
  FollowerPressureKernel(const Mesh& mesh, const DofMap& dofs, std::vector<BoundaryEdge> edges, int pressure,
                         double sign = 1.0)
      : edges_(std::move(edges)), pressure_(pressure), sign_(sign) {
    const int fx = dofs.field_index("position");
    dofs_.resize(edges_.size() * kSize);
    for (size_t k = 0; k < edges_.size(); ++k)
      for (int j = 0; j < 3; ++j) {
        const int node = mesh.element(edges_[k].element)[ref::edge_nodes[edges_[k].edge][j]];
        dofs_[k * kSize + j] = dofs.node_dof(fx, node, 0);
        dofs_[k * kSize + 3 + j] = dofs.node_dof(fx, node, 1);
      }
  }

  std::string name() const { return "follower-pressure"; }
  int num_items() const { return static_cast<int>(edges_.size()); }
  void item_dofs(int item, int* out) const { std::copy_n(&dofs_[static_cast<size_t>(item) * kSize], kSize, out); }

  template <class T, class P>
  Status evaluate(int item, const T* u, const P* params, T* r) const {
    const int e = edges_[item].edge;
    // edges 0 and 1 run with the element on their left: outward n ds = (ty, -tx) ds; 2 and 3
    // the other way round
    const double orient = (e == 0 || e == 1) ? 1.0 : -1.0;
    const ref::Tables& tb = ref::tables();
    const P p = sign_ * params[pressure_];
    for (int i = 0; i < kSize; ++i) r[i] = 0.0;
    for (int q = 0; q < ref::kEdgeQp; ++q) {
      const double s = e == 0 || e == 2 ? tb.edge_s[e][q] : tb.edge_t[e][q];
      T tx = 0.0, ty = 0.0;
      for (int j = 0; j < 3; ++j) {
        tx += ref::lagrange2_d(j, s) * u[j];
        ty += ref::lagrange2_d(j, s) * u[3 + j];
      }
      const T nx = orient * ty, ny = -orient * tx;  // n ds / (weight ds_ref)
      for (int j = 0; j < 3; ++j) {
        const double N = ref::lagrange2(j, s) * tb.edge_w[q];
        r[j] += (p * N) * nx;
        r[3 + j] += (p * N) * ny;
      }
    }
    return {};
  }

 private:
  std::vector<BoundaryEdge> edges_;
  std::vector<int> dofs_;
  int pressure_;
  double sign_;
};

}  // namespace keller
