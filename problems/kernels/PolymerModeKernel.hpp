// Element kernel of one further polymer mode of a multi-mode fluid (the first mode, with the
// solvent, pressure, DEVSS and velocity-gradient projection, is ViscoelasticFlowKernel's) on one
// 9-node element of a fixed or a moving mesh. The mode k's conformation M_k (or its logarithm) is
// transported like the first mode's (ConformationTransport.hpp, SUPG-weighted), with its own
// relaxation time lambda_k = t_k lambda and modulus w_k (1 - beta) Gamma / (t_k Wi)
// (FlowParameters.hpp, PolymerMode), by the velocity and stretched by the same interpolated
// velocity gradient L; its polymer stress tau_k = modulus_k (s0 I + s1 M_k) is added to the
// momentum rows, int dphi_a/dx_j tau_k,ij dA (Momentum.hpp's divergence form). The total stress
// is the sum over the modes.
//
// Local unknowns: v_x (9), v_y (9), L_xx L_xy L_yx L_yy (4 each), then the mode's conformation
// components (4 each): 34 + 4 NC rows; on a moving mesh then x and y of nodes 0..8, whose rows
// the kernel does not write. The rows of L are not written either: L is the first mode's
// kernel's projection.
#pragma once

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "core/AutoDiff.hpp"
#include "core/DofMap.hpp"
#include "core/ElementGeometry.hpp"
#include "core/Mesh.hpp"
#include "core/Status.hpp"
#include "problems/kernels/ConformationTransport.hpp"
#include "problems/kernels/Devss.hpp"
#include "problems/kernels/FlowParameters.hpp"
#include "problems/kernels/Momentum.hpp"
#include "problems/kernels/MovingGeometry.hpp"
#include "problems/kernels/Supg.hpp"
#include "problems/kernels/ViscoelasticFlowKernel.hpp"
#include "problems/laws/ConstitutiveLaw.hpp"

namespace keller {

template <int NC, bool Moving = false>
class PolymerModeKernel {
 public:
  static_assert(NC == 3 || NC == 4, "3 or 4 conformation components");
  static constexpr int kGradient = 18;
  static constexpr int kConf = 34;
  static constexpr int kRows = kConf + 4 * NC;
  static constexpr int kSize = kRows + (Moving ? 18 : 0);

  // o.mode: the mode (its field, time parameter and share); o.source is not used (a manufactured
  // solution's sources are the first mode's).
  PolymerModeKernel(const Mesh& mesh, const DofMap& dofs, std::vector<int> elements,
                    const std::vector<std::array<QpGeometry<double>, ref::kQp>>* geometry, FlowParameterIndices p,
                    ViscoelasticKernelOptions o)
      : geometry_(geometry), elements_(std::move(elements)), p_(p), o_(std::move(o)) {
    const int fv = dofs.field_index("velocity"), fl = dofs.field_index("gradient"),
              fm = dofs.field_index(o_.mode.field);
    if (dofs.num_components(fm) != NC) throw std::logic_error("mode field has the wrong number of components");
    dofs_.resize(elements_.size() * kSize);
    size_.resize(elements_.size());
    for (size_t k = 0; k < elements_.size(); ++k) {
      int* d = &dofs_[k * kSize];
      dofs.element_dofs(fv, elements_[k], d);
      dofs.element_dofs(fl, elements_[k], d + kGradient);
      dofs.element_dofs(fm, elements_[k], d + kConf);
      if constexpr (Moving) dofs.element_dofs(dofs.field_index("position"), elements_[k], d + kRows);
      size_[k] = element_size((*geometry_)[k]);
    }
    (void)mesh;
  }

  std::string name() const { return "polymer-mode-" + o_.mode.field; }
  int num_items() const { return static_cast<int>(elements_.size()); }
  void item_dofs(int item, int* out) const { std::copy_n(&dofs_[static_cast<size_t>(item) * kSize], kSize, out); }

  template <class T, class P>
  Status evaluate(int item, const T* u, const P* params, T* r) const {
    if constexpr (Moving) {
      T xy[9][2];
      std::array<QpGeometry<T>, ref::kQp> geo;
      if (!moving_geometry(u + kRows, xy, geo)) {
        for (int i = 0; i < kRows; ++i) r[i] = 0.0;
        return {StatusCode::InvalidState,
                "fluid element " + std::to_string(elements_[item]) + " is inverted (det J <= 0)"};
      }
      return evaluate_on(u, params, r, geo, element_size(geo));
    } else {
      return evaluate_on(u, params, r, (*geometry_)[item], size_[item]);
    }
  }

  // The conformation rows' time terms (ViscoelasticFlowKernel::rate's, for this mode).
  template <class W>
  Status rate(int item, const double* u, const W* udot, const double* params, W* r) const {
    std::array<QpGeometry<double>, ref::kQp> moved;
    double h = 0;
    if constexpr (Moving) {
      double xy[9][2];
      if (!moving_geometry(u + kRows, xy, moved))
        return {StatusCode::InvalidState,
                "fluid element " + std::to_string(elements_[item]) + " is inverted (det J <= 0)"};
      h = element_size(moved);
    } else {
      h = size_[item];
    }
    const auto& geo = Moving ? moved : (*geometry_)[item];
    const double Gamma = velocity_scale(p_, params);
    const bool ale = Moving && o_.ale;
    for (int i = 0; i < kRows; ++i) r[i] = 0.0;
    for (int q = 0; q < ref::kQp; ++q) {
      const QpGeometry<double>& g = geo[q];
      const VelocityAt<double> s = velocity_at(u, u + 9, q, g);
      const double tau = supg_time_scale(o_.supg, h, s.v, Gamma);
      W xdot[2];
      if constexpr (Moving)
        if (ale) mesh_velocity(q, udot + kRows, xdot);
      const ConformationAt<NC, double, double> mq(u + kConf, q, g);
      add_conformation_rate<NC>(q, g, tau, s.v, udot + kConf, mq, ale ? xdot : nullptr, r + kConf);
    }
    return {};
  }

 private:
  template <class T, class P, class G>
  Status evaluate_on(const T* u, const P* params, T* r, const std::array<QpGeometry<G>, ref::kQp>& geo,
                     const G& h) const {
    const P Gamma = velocity_scale(p_, params);
    const P Wi = params[p_.Wi];
    const P lambda = mode_relaxation_time(P(Wi / Gamma), o_.mode, params);
    const P modulus = mode_modulus(polymer_modulus(p_, params), o_.mode, params);
    const T* mc = u + kConf;
    for (int i = 0; i < kRows; ++i) r[i] = 0.0;
    if (!(value_of(Wi) > 0.0)) return {StatusCode::InvalidState, "Wi must be positive in the viscoelastic equations"};
    const LawConstants<P> law = law_constants(p_.law, params);
    const P* xi = p_.law.xi >= 0 ? &params[p_.law.xi] : nullptr;
    const char* inadmissible = inadmissible_state(o_.model);
    if (inadmissible)
      if (Status st = check_conformation_nodes<NC>(o_.model, o_.log_conformation, mc, law, inadmissible); !st.is_ok())
        return st;
    for (int q = 0; q < ref::kQp; ++q) {
      const QpGeometry<G>& g = geo[q];
      const VelocityAt<T> s = velocity_at(u, u + 9, q, g);
      T L[2][2];
      interpolated_gradient(u + kGradient, q, L);
      const ConformationAt<NC, T, G> mq(mc, q, g);
      const Conformation<T> M = conformation_of<NC>(mq.m, o_.log_conformation);
      const Relaxation<T> k = relaxation(o_.model, NC == 4, M, law);
      if (inadmissible && !(value_of(k.factor) > 0.0)) return {StatusCode::InvalidState, inadmissible};
      const Conformation<T> tp = polymer_stress(M, k, modulus);
      // the mode's polymer stress in the momentum rows
      const G w = g.wdetJ;
      for (int a = 0; a < 9; ++a) {
        const G dx = g.dN2dx[a][0], dy = g.dN2dx[a][1];
        r[a] += w * (dx * tp.xx + dy * tp.xy);
        r[9 + a] += w * (dx * tp.xy + dy * tp.yy);
      }
      // its transport, SUPG-weighted
      const T inv_lambda = inverse_relaxation_time(o_.model, lambda, L, Gamma, o_.owens);
      const T tau = supg_time_scale(o_.supg, h, s.v, Gamma);
      T R[NC];
      conformation_transport(mq, M, s.v, L, k, inv_lambda, o_.log_conformation, xi, nullptr, g.x, R);
      add_conformation_rows<NC>(q, g, tau, s.v, R, r + kConf);
    }
    return {};
  }

  const std::vector<std::array<QpGeometry<double>, ref::kQp>>* geometry_;
  std::vector<int> elements_;
  std::vector<int> dofs_;
  std::vector<double> size_;  // sqrt(element area)
  FlowParameterIndices p_;
  ViscoelasticKernelOptions o_;
};

}  // namespace keller
