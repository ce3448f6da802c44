// Element kernel of steady viscoelastic flow by DEVSS-TG/SUPG (method.md) on one 9-node element
// of a fixed mesh, or of a moving one (Moving = true: the node positions are unknowns and the
// geometry, the SUPG element size and the pressure basis are computed from them, so the
// Jacobian holds the shape derivatives): Q2 velocity, P1-discontinuous pressure, Q1 interpolated velocity gradient L
// (4 components, not symmetric), Q1 conformation M (xx, xy, yy, and zz where it is an unknown)
// or its logarithm Psi.
//
// Residuals (chi: Q1, phi: Q2, psi: P1disc; K_ij = d v_i / d x_j):
//   momentum     int phi (Re/Gamma) v . grad v + grad phi : [-P I + beta (K + K^T)
//                    + beta_a ((K + K^T) - (L + L^T)) + tau_p]
//   continuity   - int psi div v
//   gradient     int chi [L - K + (div v / 2) I]
//   conformation int (chi + tau_supg v . grad chi) [v . grad M - L M - M L^T + (f M - I) / lambda_eff]
//   log form     int (chi + tau_supg v . grad chi) [v . grad Psi - T(L, Psi) - (exp(-Psi) - f I) / lambda_eff]
//   zz (FENE-P, when an unknown)  [v . grad M_zz + (f M_zz - 1) / lambda_eff], log: - (exp(-psi_zz) - f)
// with tau_p = (1 - beta) (Gamma / Wi) (f M - I), lambda = Wi / Gamma, lambda_eff = lambda
// eta_p(gdot(L)) / eta_p0 for Owens (in the conformation equation only). Optional volume
// sources (FlowSource.hpp, manufactured solutions) are subtracted: int phi . force from the
// momentum rows, and the constitutive source inside the SUPG-weighted bracket.
//
// Local unknowns: v_x (9), v_y (9), P (3), L_xx L_xy L_yx L_yy (4 each), then the conformation
// components (4 each): 37 + 4 NC rows; on a moving mesh then x and y of nodes 0..8, whose rows
// the kernel does not write.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "core/AutoDiff.hpp"
#include "core/DofMap.hpp"
#include "core/ElementGeometry.hpp"
#include "core/Mesh.hpp"
#include "core/Status.hpp"
#include "problems/ConstitutiveLaw.hpp"
#include "problems/FlowSource.hpp"
#include "problems/LogConformation.hpp"

namespace keller {

// Indices of the ParameterSet entries a viscoelastic kernel reads (-1: absent).
struct ViscoelasticParameterIndices {
  int Re = -1;     // -1: no inertia
  int Gamma = -1;  // velocity scale; -1: 1
  int Wi = -1;
  int beta = -1;
  int b = -1;      // FENE-P only
};

struct ViscoelasticKernelOptions {
  FluidModel model = FluidModel::OldroydB;
  bool log_conformation = false;
  bool inertia = false;
  double devss = -1.0;            // beta_a; negative: 1 - beta
  bool supg_local = true;         // tau = scale h_e / |v| (guarded), or global scale h_c / v_c
  double supg_scale = 1.0;
  double supg_velocity_floor = 1e-3;  // |v| is floored at this fraction of the velocity scale
  double global_size = 1.0;       // h_c for the global option
  OwensParameters owens;
  std::shared_ptr<const FlowSource> source;  // volume sources; null in every physical problem
};

// The conformation tensor from its unknowns at a point: M itself, or exp(Psi) in the log form;
// M_zz = 1 unless it is an unknown (NC = 4).
template <int NC, class T>
Conformation<T> conformation_of(const T* m, bool log_form) {
  Conformation<T> M{m[0], m[1], m[2], T(1.0)};
  if (log_form) {
    const Sym2<T> E = sym_exp(Sym2<T>{m[0], m[1], m[2]});
    M = {E.xx, E.xy, E.yy, T(1.0)};
  }
  if constexpr (NC == 4) {
    using std::exp;
    M.zz = log_form ? T(exp(m[3])) : m[3];
  }
  return M;
}

// Number of conformation unknowns per node: 3, or 4 for FENE-P with a dynamic M_zz.
template <int NC, bool Moving = false>
class ViscoelasticFlowKernel {
 public:
  static_assert(NC == 3 || NC == 4, "3 or 4 conformation components");
  static constexpr int kConf = 37;
  static constexpr int kRows = kConf + 4 * NC;
  static constexpr int kSize = kRows + (Moving ? 18 : 0);

  ViscoelasticFlowKernel(const Mesh& mesh, const DofMap& dofs, std::vector<int> elements,
                         const std::vector<std::array<QpGeometry<double>, ref::kQp>>* geometry,
                         ViscoelasticParameterIndices p, ViscoelasticKernelOptions o)
      : mesh_(&mesh), geometry_(geometry), elements_(std::move(elements)), p_(p), o_(o) {
    const int fv = dofs.field_index("velocity"), fp = dofs.field_index("pressure"),
              fl = dofs.field_index("gradient"), fm = dofs.field_index("conformation");
    if (dofs.num_components(fm) != NC) throw std::logic_error("conformation field has the wrong number of components");
    dofs_.resize(elements_.size() * kSize);
    size_.resize(elements_.size());
    for (size_t k = 0; k < elements_.size(); ++k) {
      int* d = &dofs_[k * kSize];
      dofs.element_dofs(fv, elements_[k], d);
      dofs.element_dofs(fp, elements_[k], d + 18);
      dofs.element_dofs(fl, elements_[k], d + 21);
      dofs.element_dofs(fm, elements_[k], d + kConf);
      if constexpr (Moving) dofs.element_dofs(dofs.field_index("position"), elements_[k], d + kRows);
      double area = 0;
      for (const auto& g : (*geometry_)[k]) area += g.wdetJ;
      size_[k] = std::sqrt(area);
    }
  }

  std::string name() const { return std::string("viscoelastic-") + to_string(o_.model); }
  int num_items() const { return static_cast<int>(elements_.size()); }
  void item_dofs(int item, int* out) const { std::copy_n(&dofs_[static_cast<size_t>(item) * kSize], kSize, out); }

  template <class T, class P>
  Status evaluate(int item, const T* u, const P* params, T* r) const {
    if constexpr (Moving) {
      using std::sqrt;
      T xy[9][2];
      for (int a = 0; a < 9; ++a) {
        xy[a][0] = u[kRows + a];
        xy[a][1] = u[kRows + 9 + a];
      }
      std::array<QpGeometry<T>, ref::kQp> geo;
      if (!map_element(xy, geo)) {
        for (int i = 0; i < kRows; ++i) r[i] = 0.0;
        return inverted(item);
      }
      T area = 0.0;
      for (const auto& g : geo) area += g.wdetJ;
      return evaluate_on(u, params, r, geo, xy[4], T(sqrt(area)));
    } else {
      const auto& c = mesh_->node(mesh_->element(elements_[item])[4]);
      const double centre[2] = {c[0], c[1]};
      return evaluate_on(u, params, r, (*geometry_)[item], centre, size_[item]);
    }
  }

  // Mass matrix of the time-dependent form: (Re/Gamma) int phi phi on velocity rows and the
  // SUPG-weighted int (chi + tau v . grad chi) chi on conformation rows.
  Status mass(int item, const double* u, const double* params, double* B) const {
    std::array<QpGeometry<double>, ref::kQp> moved;
    double h = 0;
    if constexpr (Moving) {
      double xy[9][2];
      for (int a = 0; a < 9; ++a) {
        xy[a][0] = u[kRows + a];
        xy[a][1] = u[kRows + 9 + a];
      }
      if (!map_element(xy, moved)) return inverted(item);
      for (const auto& g : moved) h += g.wdetJ;
      h = std::sqrt(h);
    } else {
      h = size_[item];
    }
    const auto& geo = Moving ? moved : (*geometry_)[item];
    const ref::Tables& tb = ref::tables();
    const double Gamma = p_.Gamma >= 0 ? params[p_.Gamma] : 1.0;
    const double rho = o_.inertia ? params[p_.Re] / Gamma : 0.0;
    std::fill(B, B + kRows * kSize, 0.0);
    for (int q = 0; q < ref::kQp; ++q) {
      const QpGeometry<double>& g = geo[q];
      double v[2] = {0, 0};
      for (int a = 0; a < 9; ++a) {
        v[0] += tb.N2[q][a] * u[a];
        v[1] += tb.N2[q][a] * u[9 + a];
      }
      const double floor = o_.supg_velocity_floor * Gamma;
      const double tau = o_.supg_local ? o_.supg_scale * h / std::sqrt(v[0] * v[0] + v[1] * v[1] + floor * floor)
                                       : o_.supg_scale * o_.global_size / Gamma;
      for (int a = 0; a < 9; ++a)
        for (int b = 0; b < 9; ++b) {
          const double mab = rho * g.wdetJ * tb.N2[q][a] * tb.N2[q][b];
          B[a * kSize + b] += mab;
          B[(9 + a) * kSize + 9 + b] += mab;
        }
      for (int k = 0; k < 4; ++k) {
        const double wk = g.wdetJ * (tb.N1[q][k] + tau * (v[0] * g.dN1dx[k][0] + v[1] * g.dN1dx[k][1]));
        for (int l = 0; l < 4; ++l)
          for (int c = 0; c < NC; ++c) B[(kConf + 4 * c + k) * kSize + kConf + 4 * c + l] += wk * tb.N1[q][l];
      }
    }
    return {};
  }

 private:
  Status inverted(int item) const {
    return {StatusCode::InvalidState, "fluid element " + std::to_string(elements_[item]) + " is inverted (det J <= 0)"};
  }

  // The residual on an element with Gauss-point geometry geo (scalar G: double on a fixed mesh,
  // T on a moving one), centre node position centre and size h = sqrt(area).
  template <class T, class P, class G>
  Status evaluate_on(const T* u, const P* params, T* r, const std::array<QpGeometry<G>, ref::kQp>& geo,
                     const G (&centre)[2], const G& h) const {
    using std::sqrt;
    const ref::Tables& tb = ref::tables();
    const P Gamma = p_.Gamma >= 0 ? params[p_.Gamma] : P(1.0);
    const P Wi = params[p_.Wi], beta = params[p_.beta];
    const P lambda = Wi / Gamma;
    const P modulus = (1.0 - beta) * Gamma / Wi;
    const P beta_a = o_.devss >= 0 ? P(o_.devss) : P(1.0 - beta);
    const T* vx = u;
    const T* vy = u + 9;
    const T* pc = u + 18;
    const T* Lc = u + 21;   // Lxx[4], Lxy[4], Lyx[4], Lyy[4]
    const T* mc = u + kConf;  // component c at Q1 node k: mc[4 c + k]
    for (int i = 0; i < kRows; ++i) r[i] = 0.0;
    if (!(value_of(Wi) > 0.0)) return {StatusCode::InvalidState, "Wi must be positive in the viscoelastic equations"};
    if (o_.model == FluidModel::FeneP) {
      // tr M < 3b at the conformation nodes themselves, not only at the Gauss points between them
      for (int k = 0; k < 4; ++k) {
        T m[NC];
        for (int c = 0; c < NC; ++c) m[c] = mc[4 * c + k];
        const T f = peterlin(o_.model, NC == 4, conformation_of<NC>(m, o_.log_conformation), params[p_.b]);
        if (!(value_of(f) > 0.0)) return {StatusCode::InvalidState, "FENE-P: tr M reached 3b at a conformation node"};
      }
    }

    for (int q = 0; q < ref::kQp; ++q) {
      const QpGeometry<G>& g = geo[q];
      const G w = g.wdetJ;
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
      T L[2][2] = {{T(0.0), T(0.0)}, {T(0.0), T(0.0)}};
      T m[NC], dm[NC][2];  // conformation (or Psi) components and their gradients
      for (int c = 0; c < NC; ++c) {
        m[c] = 0.0;
        dm[c][0] = 0.0;
        dm[c][1] = 0.0;
      }
      for (int k = 0; k < 4; ++k) {
        const double N = tb.N1[q][k];
        L[0][0] += N * Lc[k];
        L[0][1] += N * Lc[4 + k];
        L[1][0] += N * Lc[8 + k];
        L[1][1] += N * Lc[12 + k];
        for (int c = 0; c < NC; ++c) {
          m[c] += N * mc[4 * c + k];
          dm[c][0] += g.dN1dx[k][0] * mc[4 * c + k];
          dm[c][1] += g.dN1dx[k][1] * mc[4 * c + k];
        }
      }
      // conformation tensor M (in-plane and zz) and the Peterlin factor
      const Conformation<T> M = conformation_of<NC>(m, o_.log_conformation);
      T f = 1.0;
      if (o_.model == FluidModel::FeneP) {
        f = peterlin(o_.model, NC == 4, M, params[p_.b]);
        if (!(value_of(f) > 0.0)) return {StatusCode::InvalidState, "FENE-P: tr M reached 3b"};
      }
      const Conformation<T> tp = polymer_stress(M, f, modulus);
      const T txx = tp.xx, txy = tp.xy, tyy = tp.yy;

      // momentum and continuity
      const T devss_xy = beta_a * ((K[0][1] + K[1][0]) - (L[0][1] + L[1][0]));
      const T Txx = 2.0 * beta * K[0][0] + 2.0 * beta_a * (K[0][0] - L[0][0]) + txx - pressure;
      const T Tyy = 2.0 * beta * K[1][1] + 2.0 * beta_a * (K[1][1] - L[1][1]) + tyy - pressure;
      const T Txy = beta * (K[0][1] + K[1][0]) + devss_xy + txy;
      T conv[2] = {T(0.0), T(0.0)};
      if (o_.inertia) {
        const P rho = params[p_.Re] / Gamma;
        conv[0] = rho * (v[0] * K[0][0] + v[1] * K[0][1]);
        conv[1] = rho * (v[0] * K[1][0] + v[1] * K[1][1]);
      }
      const double x[2] = {value_of(g.x[0]), value_of(g.x[1])};
      if (o_.source && o_.source->momentum) {
        double force[2];
        o_.source->momentum(x, force);
        conv[0] -= force[0];
        conv[1] -= force[1];
      }
      for (int a = 0; a < 9; ++a) {
        const double N = tb.N2[q][a];
        const G dx = g.dN2dx[a][0], dy = g.dN2dx[a][1];
        r[a] += w * (N * conv[0] + dx * Txx + dy * Txy);
        r[9 + a] += w * (N * conv[1] + dx * Txy + dy * Tyy);
      }
      const T div = K[0][0] + K[1][1];
      for (int k = 0; k < 3; ++k) r[18 + k] -= (w * psi[k]) * div;

      // velocity-gradient projection (traceless in plane: tr I = 2)
      const T rl[4] = {L[0][0] - K[0][0] + 0.5 * div, L[0][1] - K[0][1], L[1][0] - K[1][0], L[1][1] - K[1][1] + 0.5 * div};
      for (int k = 0; k < 4; ++k)
        for (int c = 0; c < 4; ++c) r[21 + 4 * c + k] += (w * tb.N1[q][k]) * rl[c];

      // conformation: relaxation time and SUPG
      T inv_lambda = 1.0 / lambda;
      if (o_.model == FluidModel::Owens) {
        const T dxx = L[0][0], dyy = L[1][1], dxy = 0.5 * (L[0][1] + L[1][0]);
        const T gdot2 = 2.0 * (dxx * dxx + dyy * dyy + 2.0 * dxy * dxy);
        inv_lambda = inv_lambda / owens_factor(gdot2, Gamma, o_.owens);
      }
      T tau;
      if (o_.supg_local) {
        const P floor = o_.supg_velocity_floor * Gamma;
        tau = o_.supg_scale * h / sqrt(v[0] * v[0] + v[1] * v[1] + floor * floor);
      } else {
        tau = o_.supg_scale * o_.global_size / Gamma;
      }
      T R[NC];
      if (o_.log_conformation) {
        const Sym2<T> rate = log_conformation_rate(Sym2<T>{m[0], m[1], m[2]}, L, f, inv_lambda);
        R[0] = v[0] * dm[0][0] + v[1] * dm[0][1] + rate.xx;
        R[1] = v[0] * dm[1][0] + v[1] * dm[1][1] + rate.xy;
        R[2] = v[0] * dm[2][0] + v[1] * dm[2][1] + rate.yy;
        if constexpr (NC == 4) {
          using std::exp;
          R[3] = v[0] * dm[3][0] + v[1] * dm[3][1] - inv_lambda * (exp(-m[3]) - f);
        }
      } else {
        const Conformation<T> rate = conformation_rate(M, L, f, inv_lambda);
        R[0] = v[0] * dm[0][0] + v[1] * dm[0][1] + rate.xx;
        R[1] = v[0] * dm[1][0] + v[1] * dm[1][1] + rate.xy;
        R[2] = v[0] * dm[2][0] + v[1] * dm[2][1] + rate.yy;
        if constexpr (NC == 4) R[3] = v[0] * dm[3][0] + v[1] * dm[3][1] + rate.zz;
      }
      if (o_.source && o_.source->constitutive) {
        double s[4] = {0.0, 0.0, 0.0, 0.0};
        o_.source->constitutive(x, s);
        for (int c = 0; c < NC; ++c) R[c] -= s[c];
      }
      for (int k = 0; k < 4; ++k) {
        const T weight = w * (tb.N1[q][k] + tau * (v[0] * g.dN1dx[k][0] + v[1] * g.dN1dx[k][1]));
        for (int c = 0; c < NC; ++c) r[kConf + 4 * c + k] += weight * R[c];
      }
    }
    return {};
  }

  const Mesh* mesh_;
  const std::vector<std::array<QpGeometry<double>, ref::kQp>>* geometry_;
  std::vector<int> elements_;
  std::vector<int> dofs_;
  std::vector<double> size_;  // sqrt(element area)
  ViscoelasticParameterIndices p_;
  ViscoelasticKernelOptions o_;
};

}  // namespace keller
