// Element kernel of the incompressible neo-Hookean solid in plane strain, total Lagrangian,
// mixed form: Q2 positions x (the unknowns are the deformed positions themselves), P1
// discontinuous pressure pi in reference coordinates.
//
// Strain energy per reference area (stresses in units of G): W = (tr C - 2)/2 - pi (J - 1),
// C = F^T F, F = dx/dX, J = det F. Its first Piola-Kirchhoff stress is
//   P = F - pi J F^-T = F - pi cof(F),   cof(F) = [[F_yy, -F_yx], [-F_xy, F_xx]],
// and the Cauchy stress sigma = P F^T / J = B / J - pi I, which is model.md's -pi I + B where the
// constraint J = 1 holds. Residual (model.md notation):
//   equilibrium R_ai = int_Omega0 P_iJ dphi_a/dX_J dA0
//   constraint  R_k  = - int_Omega0 psi_k (J - 1) dA0,  psi = (1, X - Xc, Y - Yc)
// Both are polynomial in the unknowns (no F^-1 appears), and the constraint rows are minus the
// transpose of the pressure columns, so the Jacobian is symmetric. J of a Q2 map is a polynomial
// of degree 3 per direction, which the 3x3 Gauss rule integrates exactly: with psi_0 = 1 every
// element keeps its reference area to rounding.
//
// The reference geometry is affine in the wall thickness t: X_a = X0_a + t X1_a, so dF/dt comes
// out of the same dual-number evaluation (the reference map is computed in the parameter scalar).
//
// Local unknowns (21): x at nodes 0..8, y at nodes 0..8, pi coefficients 0..2.
#pragma once

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/AffineReference.hpp"
#include "core/DofMap.hpp"
#include "core/ElementGeometry.hpp"
#include "core/Mesh.hpp"
#include "core/Status.hpp"

namespace keller {

class NeoHookeanSolidKernel {
 public:
  static constexpr int kSize = 21;

  NeoHookeanSolidKernel(const Mesh& mesh, const DofMap& dofs, std::vector<int> elements,
                        const AffineReference* reference)
      : mesh_(&mesh), reference_(reference), elements_(std::move(elements)) {
    const int fx = dofs.field_index("position"), fp = dofs.field_index("solid_pressure");
    dofs_.resize(elements_.size() * kSize);
    for (size_t k = 0; k < elements_.size(); ++k) {
      dofs.element_dofs(fx, elements_[k], &dofs_[k * kSize]);
      dofs.element_dofs(fp, elements_[k], &dofs_[k * kSize + 18]);
    }
  }

  std::string name() const { return "neo-hookean-solid"; }
  int num_items() const { return static_cast<int>(elements_.size()); }
  void item_dofs(int item, int* out) const { std::copy_n(&dofs_[static_cast<size_t>(item) * kSize], kSize, out); }

  template <class T, class P>
  Status evaluate(int item, const T* u, const P* params, T* r) const {
    const int e = elements_[item];
    P X[9][2];
    reference_->element(*mesh_, e, params, X);
    std::array<QpGeometry<P>, ref::kQp> geo;
    if (!map_element(X, geo))
      return {StatusCode::InvalidState, fmt::format("solid element {} has a degenerate reference shape", e)};
    const T* x = u;
    const T* y = u + 9;
    const T* pc = u + 18;
    for (int i = 0; i < kSize; ++i) r[i] = 0.0;
    bool inverted = false;
    for (int q = 0; q < ref::kQp; ++q) {
      const QpGeometry<P>& g = geo[q];
      T F[2][2] = {{T(0.0), T(0.0)}, {T(0.0), T(0.0)}};  // F_iJ = dx_i / dX_J
      for (int a = 0; a < 9; ++a)
        for (int J = 0; J < 2; ++J) {
          F[0][J] += x[a] * g.dN2dx[a][J];
          F[1][J] += y[a] * g.dN2dx[a][J];
        }
      const T detF = F[0][0] * F[1][1] - F[0][1] * F[1][0];
      if (!(detF > 0.0)) inverted = true;
      const P psi[3] = {P(1.0), g.x[0] - X[4][0], g.x[1] - X[4][1]};
      const T pi = psi[0] * pc[0] + psi[1] * pc[1] + psi[2] * pc[2];
      // P = F - pi cof(F)
      const T Pxx = F[0][0] - pi * F[1][1], PxY = F[0][1] + pi * F[1][0];
      const T PyX = F[1][0] + pi * F[0][1], Pyy = F[1][1] - pi * F[0][0];
      const P w = g.wdetJ;
      for (int a = 0; a < 9; ++a) {
        const P dX = g.dN2dx[a][0], dY = g.dN2dx[a][1];
        r[a] += w * (Pxx * dX + PxY * dY);
        r[9 + a] += w * (PyX * dX + Pyy * dY);
      }
      const T dJ = detF - 1.0;
      for (int k = 0; k < 3; ++k) r[18 + k] -= (w * psi[k]) * dJ;
    }
    if (inverted) return {StatusCode::InvalidState, fmt::format("solid element {} is inverted (det F <= 0)", e)};
    return {};
  }

 private:
  const Mesh* mesh_;
  const AffineReference* reference_;
  std::vector<int> elements_;
  std::vector<int> dofs_;
};

}  // namespace keller
