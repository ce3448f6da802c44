// The wall's inertia in the time-dependent form: rho* int_Omega0 phi_a dw_i/dt dA0 in the solid's
// equilibrium rows (total Lagrangian: the reference density, J = 1), w the wall velocity, a Q2
// field of its own whose rows are the kinematics w = dx/dt (RateConstraintTerm). rho* is the
// solid's inertia in the problem's units (collapsible channel: density ratio x Re / Gamma, time in
// eta0 / G), a function of the parameters. Only B carries it: the steady residual and its
// Jacobian are zero (w = 0 at a steady state, from the kinematic rows).
//
// Local unknowns (36): x at nodes 0..8, y at nodes 0..8 (the rows: the solid's equilibrium), then
// w_x at nodes 0..8, w_y at nodes 0..8 (the columns of B).
#pragma once

#include <algorithm>
#include <array>
#include <functional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/AffineReference.hpp"
#include "core/DofMap.hpp"
#include "core/ElementGeometry.hpp"
#include "core/Mesh.hpp"
#include "core/ParameterSet.hpp"
#include "core/Term.hpp"

namespace keller {

class SolidInertiaTerm final : public Term {
 public:
  static constexpr int kSize = 36, kRows = 18;
  using Density = std::function<double(const ParameterSet&)>;

  SolidInertiaTerm(const Mesh& mesh, const DofMap& dofs, std::vector<int> elements, const AffineReference* reference,
                   const ParameterSet& params, Density density)
      : mesh_(&mesh),
        reference_(reference),
        params_(&params),
        density_(std::move(density)),
        elements_(std::move(elements)) {
    const int fx = dofs.field_index("position"), fw = dofs.field_index("wall_velocity");
    dofs_.resize(elements_.size() * kSize);
    for (size_t k = 0; k < elements_.size(); ++k) {
      dofs.element_dofs(fx, elements_[k], &dofs_[k * kSize]);
      dofs.element_dofs(fw, elements_[k], &dofs_[k * kSize + 18]);
    }
  }

  std::string name() const override { return "solid-inertia"; }
  int num_items() const override { return static_cast<int>(elements_.size()); }
  int local_size() const override { return kSize; }
  int local_rows() const override { return kRows; }
  void item_dofs(int item, int* out) const override {
    std::copy_n(&dofs_[static_cast<size_t>(item) * kSize], kSize, out);
  }
  Status residual(int, const double*, double* r) const override {
    std::fill_n(r, kRows, 0.0);
    return {};
  }
  Status jacobian(int, const double*, double* r, double* J) const override {
    std::fill_n(r, kRows, 0.0);
    std::fill_n(J, kRows * kSize, 0.0);
    return {};
  }
  Status parameter_derivative(int, int, const double*, double* dr) const override {
    std::fill_n(dr, kRows, 0.0);
    return {};
  }
  // the steady residual is zero, and so are its derivatives
  bool has_directional_derivative() const override { return true; }
  Status directional_derivative(int, const double*, int, const double* const*, const double* const*,
                                double* r) const override {
    std::fill(r, r + kRows, 0.0);
    return {};
  }
  bool has_mass() const override { return true; }
  // B[a][18 + b] = B[9 + a][27 + b] = rho* int phi_a phi_b dA0 (the consistent mass matrix).
  Status mass(int item, const double*, double* B) const override {
    std::fill_n(B, kRows * kSize, 0.0);
    double M[9][9];
    const Status st = element_mass(item, M);
    if (!st.is_ok()) return st;
    for (int a = 0; a < 9; ++a)
      for (int b = 0; b < 9; ++b) {
        B[a * kSize + 18 + b] = M[a][b];
        B[(9 + a) * kSize + 27 + b] = M[a][b];
      }
    return {};
  }
  Status rate(int item, const double*, const double* udot, double* r) const override {
    double M[9][9];
    const Status st = element_mass(item, M);
    if (!st.is_ok()) return st;
    for (int a = 0; a < 9; ++a) {
      double rx = 0.0, ry = 0.0;
      for (int b = 0; b < 9; ++b) {
        rx += M[a][b] * udot[18 + b];
        ry += M[a][b] * udot[27 + b];
      }
      r[a] = rx;
      r[9 + a] = ry;
    }
    return {};
  }

 private:
  // rho* int phi_a phi_b dA0 over the reference element at the present parameters (3x3 Gauss:
  // exact for the Q2 x Q2 product on the affine reference shape up to its x-y bilinear part).
  Status element_mass(int item, double (&M)[9][9]) const {
    const int e = elements_[static_cast<size_t>(item)];
    double X[9][2];
    reference_->element(*mesh_, e, params_->values(), X);
    std::array<QpGeometry<double>, ref::kQp> geo;
    if (!map_element(X, geo))
      return {StatusCode::InvalidState, fmt::format("solid element {} has a degenerate reference shape", e)};
    const double rho = density_(*params_);
    const ref::Tables& tb = ref::tables();
    for (int a = 0; a < 9; ++a)
      for (int b = 0; b < 9; ++b) M[a][b] = 0.0;
    for (int q = 0; q < ref::kQp; ++q)
      for (int a = 0; a < 9; ++a)
        for (int b = 0; b < 9; ++b) M[a][b] += rho * geo[q].wdetJ * tb.N2[q][a] * tb.N2[q][b];
    return {};
  }

  const Mesh* mesh_;
  const AffineReference* reference_;
  const ParameterSet* params_;
  Density density_;
  std::vector<int> elements_;
  std::vector<int> dofs_;
};

}  // namespace keller
