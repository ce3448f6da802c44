// Element kernel of steady incompressible Newtonian flow on one 9-node element: Q2 velocity,
// P1-discontinuous pressure in physical coordinates. On a fixed mesh the Gauss-point geometry
// is cached; on a moving mesh (Moving = true) the element's node positions are unknowns too and
// the geometry is computed from them in the unknowns' scalar type, which puts the shape
// derivatives (residual with respect to node positions) into the Jacobian.
//
// Residual (model.md notation, stresses in units of G, velocities in units of G W / eta0):
//   momentum   R_ai = int [ phi_a (Re/Gamma) (v . grad v)_i + dphi_a/dx_j T_ij ] dA
//              with T = -P I + beta (K + K^T), K_ij = d v_i / d x_j
//   continuity R_k  = - int psi_k div v dA,  psi = (1, x - xc, y - yc)
// The traction boundary term is absent: on the outflow it is the natural condition
// T_xx = 0 (-P + 2 beta dv_x/dx = 0), i.e. P = 0 for fully developed flow.
//
// Local unknowns (21): v_x at nodes 0..8, v_y at nodes 0..8, P coefficients 0..2; on a moving
// mesh then x and y of nodes 0..8 (39), whose rows this kernel does not write (kRows = 21).
// Time-dependent form: (Re/Gamma) dv/dt adds the mass block (Re/Gamma) int phi_a phi_b to the
// velocity rows; continuity has no time derivative. With Re = 0 the mass matrix is zero.
// An optional body force (FlowSource.hpp, manufactured solutions) subtracts int phi_a f_i dA.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "core/AutoDiff.hpp"
#include "core/DofMap.hpp"
#include "core/ElementGeometry.hpp"
#include "core/Mesh.hpp"
#include "core/Status.hpp"
#include "problems/FlowSource.hpp"

namespace keller {

struct NewtonianFlowParameters {
  int Re = -1;     // index of Re in the ParameterSet
  int Gamma = -1;  // index of Gamma (mean inflow velocity)
  int beta = -1;   // index of the solvent viscosity ratio; -1: beta = 1 (Newtonian)
};

template <bool Moving = false>
class NewtonianFlowKernel {
 public:
  static constexpr int kRows = 21;
  static constexpr int kSize = Moving ? 39 : 21;

  // elements: the fluid elements; geometry: their cached Gauss-point geometry (same order);
  // source: a body force, or null.
  NewtonianFlowKernel(const Mesh& mesh, const DofMap& dofs, std::vector<int> elements,
                      const std::vector<std::array<QpGeometry<double>, ref::kQp>>* geometry,
                      NewtonianFlowParameters params, bool inertia, std::shared_ptr<const FlowSource> source = nullptr)
      : mesh_(&mesh),
        geometry_(geometry),
        elements_(std::move(elements)),
        p_(params),
        inertia_(inertia),
        force_(source && source->momentum ? source : nullptr) {
    const int fv = dofs.field_index("velocity"), fp = dofs.field_index("pressure");
    dofs_.resize(elements_.size() * kSize);
    for (size_t k = 0; k < elements_.size(); ++k) {
      dofs.element_dofs(fv, elements_[k], &dofs_[k * kSize]);
      dofs.element_dofs(fp, elements_[k], &dofs_[k * kSize + 18]);
      if constexpr (Moving) dofs.element_dofs(dofs.field_index("position"), elements_[k], &dofs_[k * kSize + 21]);
    }
  }

  std::string name() const { return "newtonian-flow"; }
  int num_items() const { return static_cast<int>(elements_.size()); }
  void item_dofs(int item, int* out) const {
    std::copy_n(&dofs_[static_cast<size_t>(item) * kSize], kSize, out);
  }

  Status mass(int item, const double* u, const double* params, double* B) const {
    const ref::Tables& tb = ref::tables();
    const double rho = p_.Re >= 0 ? params[p_.Re] / params[p_.Gamma] : 0.0;
    std::fill(B, B + kRows * kSize, 0.0);
    std::array<QpGeometry<double>, ref::kQp> moved;
    if constexpr (Moving) {
      double xy[9][2];
      for (int a = 0; a < 9; ++a) {
        xy[a][0] = u[21 + a];
        xy[a][1] = u[30 + a];
      }
      if (!map_element(xy, moved)) return inverted(item);
    }
    const auto& geo = Moving ? moved : (*geometry_)[item];
    for (int q = 0; q < ref::kQp; ++q) {
      const double w = rho * geo[q].wdetJ;
      for (int a = 0; a < 9; ++a)
        for (int b = 0; b < 9; ++b) {
          const double m = w * tb.N2[q][a] * tb.N2[q][b];
          B[a * kSize + b] += m;
          B[(9 + a) * kSize + 9 + b] += m;
        }
    }
    return {};
  }

  template <class T, class P>
  Status evaluate(int item, const T* u, const P* params, T* r) const {
    if constexpr (Moving) {
      T xy[9][2];
      for (int a = 0; a < 9; ++a) {
        xy[a][0] = u[21 + a];
        xy[a][1] = u[30 + a];
      }
      std::array<QpGeometry<T>, ref::kQp> geo;
      if (!map_element(xy, geo)) {
        for (int i = 0; i < kRows; ++i) r[i] = 0.0;
        return inverted(item);
      }
      return evaluate_on(u, params, r, geo, xy[4]);
    } else {
      const auto& c = mesh_->node(mesh_->element(elements_[item])[4]);
      const double centre[2] = {c[0], c[1]};
      return evaluate_on(u, params, r, (*geometry_)[item], centre);
    }
  }

 private:
  Status inverted(int item) const {
    return {StatusCode::InvalidState, "fluid element " + std::to_string(elements_[item]) + " is inverted (det J <= 0)"};
  }

  // The residual on an element with Gauss-point geometry geo (scalar G: double on a fixed mesh,
  // T on a moving one) and centre node position centre.
  template <class T, class P, class G>
  Status evaluate_on(const T* u, const P* params, T* r, const std::array<QpGeometry<G>, ref::kQp>& geo,
                     const G (&centre)[2]) const {
    const ref::Tables& tb = ref::tables();
    const P beta = p_.beta >= 0 ? params[p_.beta] : P(1.0);
    const T* vx = u;
    const T* vy = u + 9;
    const T* pc = u + 18;
    for (int i = 0; i < kRows; ++i) r[i] = 0.0;
    for (int q = 0; q < ref::kQp; ++q) {
      const QpGeometry<G>& g = geo[q];
      T v[2] = {T(0.0), T(0.0)};
      T K[2][2] = {{T(0.0), T(0.0)}, {T(0.0), T(0.0)}};
      for (int a = 0; a < 9; ++a) {
        const double N = tb.N2[q][a];
        v[0] += N * vx[a];
        v[1] += N * vy[a];
        for (int j = 0; j < 2; ++j) {
          K[0][j] += g.dN2dx[a][j] * vx[a];
          K[1][j] += g.dN2dx[a][j] * vy[a];
        }
      }
      const G psi[3] = {G(1.0), g.x[0] - centre[0], g.x[1] - centre[1]};
      const T pressure = pc[0] + psi[1] * pc[1] + psi[2] * pc[2];
      const T shear = beta * (K[0][1] + K[1][0]);
      const T Txx = 2.0 * beta * K[0][0] - pressure;
      const T Tyy = 2.0 * beta * K[1][1] - pressure;
      const G w = g.wdetJ;
      T conv[2] = {T(0.0), T(0.0)};
      if (inertia_) {
        const P rho = params[p_.Re] / params[p_.Gamma];
        conv[0] = rho * (v[0] * K[0][0] + v[1] * K[0][1]);
        conv[1] = rho * (v[0] * K[1][0] + v[1] * K[1][1]);
      }
      if (force_) {
        const double x[2] = {value_of(g.x[0]), value_of(g.x[1])};
        double f[2];
        force_->momentum(x, f);
        conv[0] -= f[0];
        conv[1] -= f[1];
      }
      for (int a = 0; a < 9; ++a) {
        const double N = tb.N2[q][a];
        const G dx = g.dN2dx[a][0], dy = g.dN2dx[a][1];
        r[a] += w * (N * conv[0] + dx * Txx + dy * shear);
        r[9 + a] += w * (N * conv[1] + dx * shear + dy * Tyy);
      }
      const T div = K[0][0] + K[1][1];
      for (int k = 0; k < 3; ++k) r[18 + k] -= (w * psi[k]) * div;
    }
    return {};
  }

  const Mesh* mesh_;
  const std::vector<std::array<QpGeometry<double>, ref::kQp>>* geometry_;
  std::vector<int> elements_;
  std::vector<int> dofs_;
  NewtonianFlowParameters p_;
  bool inertia_;
  std::shared_ptr<const FlowSource> force_;  // null unless a body force is given
};

}  // namespace keller
