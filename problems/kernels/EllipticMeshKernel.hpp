// Element kernel of the boundary-fitted elliptic mesh equations: the positions x of the fluid
// mesh nodes are unknowns, governed by div(D_xi grad xi) = 0 and div(D_eta grad eta) = 0 for the
// map from physical to logical coordinates (xi, eta). In an element, grad xi is proportional to
// grad s (s, t the element's reference coordinates, grad s a row of the inverse of dx/ds), and
// the spacing control D is taken from the generated mesh X: D_xi grad xi = w_s grad s with
// w_s = |dX/ds| at each Gauss point (and w_t = |dX/dt| for eta). Galerkin residuals on the
// current (unknown) element:
//   R^x_a = int grad phi_a . (w_s grad s) dA,   R^y_a = int grad phi_a . (w_t grad t) dA.
// On the generated mesh of straight channel blocks, w_s grad s = (1, 0) and w_t grad t = (0, 1),
// so every interior row vanishes: the generated mesh, with its grading towards the walls and the
// ends of the deformable section, is a solution, and a deformed boundary is spread smoothly
// through the fluid with that grading. grad s dA = (dy/dt, -dx/dt) ds dt is polynomial in the
// node positions; the residual is nonlinear only through them and differentiated exactly.
//
// Rows of nodes that another equation owns (interface nodes, which the solid moves) are zeroed
// per element through a row mask; wall, inflow and outflow rows are replaced by Dirichlet
// conditions in the component that builds this kernel.
//
// Local unknowns (18): x at nodes 0..8, then y.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/DofMap.hpp"
#include "core/Mesh.hpp"
#include "core/ReferenceElement.hpp"
#include "core/Status.hpp"

namespace keller {

class EllipticMeshKernel {
 public:
  static constexpr int kSize = 18;

  // elements: fluid elements; the mesh's current node positions are the generated mesh that
  // defines the spacing weights. masked_nodes: sorted node ids whose rows this kernel leaves to
  // other equations.
  EllipticMeshKernel(const Mesh& mesh, const DofMap& dofs, std::vector<int> elements,
                     const std::vector<int>& masked_nodes)
      : elements_(std::move(elements)) {
    const int fx = dofs.field_index("position");
    const ref::Tables& tb = ref::tables();
    dofs_.resize(elements_.size() * kSize);
    weights_.resize(elements_.size());
    mask_.resize(elements_.size());
    for (size_t k = 0; k < elements_.size(); ++k) {
      const int e = elements_[k];
      dofs.element_dofs(fx, e, &dofs_[k * kSize]);
      double xy[9][2];
      mesh.element_nodes(e, xy);
      for (int q = 0; q < ref::kQp; ++q)
        for (int d = 0; d < 2; ++d) {
          double gx = 0, gy = 0;
          for (int a = 0; a < 9; ++a) {
            gx += xy[a][0] * tb.dN2[q][a][d];
            gy += xy[a][1] * tb.dN2[q][a][d];
          }
          weights_[k][q][d] = std::hypot(gx, gy);
        }
      for (int a = 0; a < 9; ++a)
        mask_[k][a] = std::binary_search(masked_nodes.begin(), masked_nodes.end(), mesh.element(e)[a]) ? 0.0 : 1.0;
    }
  }

  std::string name() const { return "elliptic-mesh"; }
  int num_items() const { return static_cast<int>(elements_.size()); }
  void item_dofs(int item, int* out) const { std::copy_n(&dofs_[static_cast<size_t>(item) * kSize], kSize, out); }

  template <class T, class P>
  Status evaluate(int item, const T* u, const P*, T* r) const {
    const ref::Tables& tb = ref::tables();
    const T* x = u;
    const T* y = u + 9;
    for (int i = 0; i < kSize; ++i) r[i] = 0.0;
    bool inverted = false;
    for (int q = 0; q < ref::kQp; ++q) {
      T J00 = 0.0, J01 = 0.0, J10 = 0.0, J11 = 0.0;  // J_ij = dx_i / ds_j
      for (int a = 0; a < 9; ++a) {
        J00 += x[a] * tb.dN2[q][a][0];
        J01 += x[a] * tb.dN2[q][a][1];
        J10 += y[a] * tb.dN2[q][a][0];
        J11 += y[a] * tb.dN2[q][a][1];
      }
      const T det = J00 * J11 - J01 * J10;
      if (!(det > 0.0)) inverted = true;
      // grad s det = (J11, -J01), grad t det = (-J10, J00); grad phi det = (dN_s J11 - dN_t J10,
      // -dN_s J01 + dN_t J00); the area element is det w_q, so one det cancels
      const double ws = weights_[item][q][0], wt = weights_[item][q][1];
      const T inv = tb.w[q] / det;
      const T fs[2] = {ws * J11 * inv, -ws * J01 * inv};
      const T ft[2] = {-wt * J10 * inv, wt * J00 * inv};
      for (int a = 0; a < 9; ++a) {
        const double ds = tb.dN2[q][a][0], dt = tb.dN2[q][a][1];
        const T gx = ds * J11 - dt * J10, gy = -ds * J01 + dt * J00;  // grad phi_a det
        r[a] += mask_[item][a] * (gx * fs[0] + gy * fs[1]);
        r[9 + a] += mask_[item][a] * (gx * ft[0] + gy * ft[1]);
      }
    }
    if (inverted)
      return {StatusCode::InvalidState, fmt::format("fluid mesh element {} is inverted (det J <= 0)", elements_[item])};
    return {};
  }

 private:
  std::vector<int> elements_;
  std::vector<int> dofs_;
  std::vector<std::array<std::array<double, 2>, ref::kQp>> weights_;
  std::vector<std::array<double, 9>> mask_;
};

}  // namespace keller
