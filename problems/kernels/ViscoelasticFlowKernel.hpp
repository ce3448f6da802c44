// Element kernel of steady viscoelastic flow by DEVSS-TG/SUPG (method.md) on one 9-node element
// of a fixed mesh, or of a moving one (Moving = true: the node positions are unknowns and the
// geometry, the SUPG element size and the pressure basis are computed from them, so the
// Jacobian holds the shape derivatives): Q2 velocity, P1-discontinuous pressure, Q1
// interpolated velocity gradient L (4 components, not symmetric), Q1 conformation M (xx, xy,
// yy, and zz where it is an unknown) or its logarithm Psi. It assembles, at each Gauss point,
// the terms of one file each:
//   momentum, continuity  Momentum.hpp, with T = -P I + beta (K + K^T) + DEVSS + tau_p
//   DEVSS                 Devss.hpp: beta_a ((K + K^T) - (L + L^T)) and the projection rows of L
//   conformation          ConformationTransport.hpp, SUPG-weighted (Supg.hpp)
// with tau_p = (1 - beta) (Gamma / Wi) (s0 I + s1 M) (the law's, ConstitutiveLaw.hpp), lambda = Wi / Gamma. Optional
// volume sources (FlowSource.hpp, manufactured solutions) are subtracted from the momentum rows and inside the
// SUPG-weighted bracket.
//
// Local unknowns: v_x (9), v_y (9), P (3), L_xx L_xy L_yx L_yy (4 each), then the conformation
// components (4 each): 37 + 4 NC rows; on a moving mesh then x and y of nodes 0..8, whose rows
// the kernel does not write.
//
// A multi-mode fluid's first mode is this kernel with the mode's time and share (options.mode);
// each further mode is PolymerModeKernel (Mode = true): the mode's conformation M_k transported the
// same way with its own relaxation time lambda_k = t_k lambda and modulus w_k (1 - beta) Gamma /
// (t_k Wi) (FlowParameters.hpp, PolymerMode), by the velocity and stretched by the first mode's
// projected gradient L, and its polymer stress added to the momentum rows, int dphi_a/dx_j
// tau_k,ij dA; no pressure, solvent, DEVSS, projection or source terms. Its local unknowns are
// v_x, v_y, L (16), then the mode's components: 34 + 4 NC rows (the rows of L not written).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <stdexcept>
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
#include "problems/kernels/FlowSource.hpp"
#include "problems/kernels/Momentum.hpp"
#include "problems/kernels/MovingGeometry.hpp"
#include "problems/kernels/Supg.hpp"
#include "problems/laws/ConstitutiveLaw.hpp"

namespace keller {

struct ViscoelasticKernelOptions {
  FluidModel model = FluidModel::OldroydB;
  bool log_conformation = false;
  bool inertia = false;
  double devss = -1.0;  // beta_a; negative: 1 - beta
  SupgOptions supg;
  OwensParameters owens;
  std::shared_ptr<const FlowSource> source;  // volume sources; null in every physical problem
  // On a moving mesh: the time derivatives at fixed points of space (ALE), not at the moving nodes.
  bool ale = false;
  // The polymer mode whose conformation the kernel transports (a multi-mode fluid's first; the
  // others: PolymerModeKernel.hpp); the default is a one-mode fluid.
  PolymerMode mode;
};

// The law's factor positive (tr M < 3b, a linear PTT's Y > 0) at the 4 conformation nodes
// themselves (mc: component c at node k is mc[4 c + k]), not only at the Gauss points between
// them; `inadmissible` names the state the law refuses.
template <int NC, class T, class P>
Status check_conformation_nodes(FluidModel model, bool log_form, const T* mc, const LawConstants<P>& law,
                                const char* inadmissible) {
  for (int k = 0; k < 4; ++k) {
    T m[NC];
    for (int c = 0; c < NC; ++c) m[c] = mc[4 * c + k];
    const Relaxation<T> rk = relaxation(model, NC == 4, conformation_of<NC>(m, log_form), law);
    if (!(value_of(rk.factor) > 0.0))
      return {StatusCode::InvalidState, std::string(inadmissible) + " at a conformation node"};
  }
  return {};
}

// Number of conformation unknowns per node: 3, or 4 for FENE-P with a dynamic M_zz. PTT's slip
// xi (the conformation form only) is read where its parameter index is set.
template <int NC, bool Moving = false, bool Mode = false>
class ViscoelasticFlowKernel {
 public:
  static_assert(NC == 3 || NC == 4, "3 or 4 conformation components");
  static constexpr int kGradient = Mode ? 18 : 21;
  static constexpr int kConf = kGradient + 16;
  static constexpr int kRows = kConf + 4 * NC;
  static constexpr int kSize = kRows + (Moving ? 18 : 0);

  ViscoelasticFlowKernel(const Mesh& mesh, const DofMap& dofs, std::vector<int> elements,
                         const std::vector<std::array<QpGeometry<double>, ref::kQp>>* geometry, FlowParameterIndices p,
                         ViscoelasticKernelOptions o)
      : mesh_(&mesh), geometry_(geometry), elements_(std::move(elements)), p_(p), o_(o) {
    const int fv = dofs.field_index("velocity"), fp = dofs.field_index("pressure"), fl = dofs.field_index("gradient"),
              fm = dofs.field_index(o_.mode.field);
    if (dofs.num_components(fm) != NC) throw std::logic_error("conformation field has the wrong number of components");
    dofs_.resize(elements_.size() * kSize);
    size_.resize(elements_.size());
    for (size_t k = 0; k < elements_.size(); ++k) {
      int* d = &dofs_[k * kSize];
      dofs.element_dofs(fv, elements_[k], d);
      if constexpr (!Mode) dofs.element_dofs(fp, elements_[k], d + 18);
      dofs.element_dofs(fl, elements_[k], d + kGradient);
      dofs.element_dofs(fm, elements_[k], d + kConf);
      if constexpr (Moving) dofs.element_dofs(dofs.field_index("position"), elements_[k], d + kRows);
      size_[k] = element_size((*geometry_)[k]);
    }
  }

  std::string name() const {
    return Mode ? "polymer-mode-" + o_.mode.field : std::string("viscoelastic-") + to_string(o_.model);
  }
  int num_items() const { return static_cast<int>(elements_.size()); }
  void item_dofs(int item, int* out) const { std::copy_n(&dofs_[static_cast<size_t>(item) * kSize], kSize, out); }

  template <class T, class P>
  Status evaluate(int item, const T* u, const P* params, T* r) const {
    if constexpr (Moving) {
      T xy[9][2];
      std::array<QpGeometry<T>, ref::kQp> geo;
      if (!moving_geometry(u + kRows, xy, geo)) {
        for (int i = 0; i < kRows; ++i) r[i] = 0.0;
        return inverted(item);
      }
      return evaluate_on(u, params, r, geo, xy[4], element_size(geo));
    } else {
      const auto& c = mesh_->node(mesh_->element(elements_[item])[4]);
      const double centre[2] = {c[0], c[1]};
      return evaluate_on(u, params, r, (*geometry_)[item], centre, size_[item]);
    }
  }

  // The time terms r = B(u) udot of the time-dependent form: (Re/Gamma) int phi dv/dt on velocity
  // rows and the SUPG-weighted int (chi + tau v . grad chi) dM/dt on conformation rows, the rates
  // at fixed points of space (on a moving mesh with options.ale: the nodal rates minus xdot . grad,
  // xdot the rates of the position unknowns).
  template <class W>
  Status rate(int item, const double* u, const W* udot, const double* params, W* r) const {
    std::array<QpGeometry<double>, ref::kQp> moved;
    double h = 0;
    if constexpr (Moving) {
      double xy[9][2];
      if (!moving_geometry(u + kRows, xy, moved)) return inverted(item);
      h = element_size(moved);
    } else {
      h = size_[item];
    }
    const auto& geo = Moving ? moved : (*geometry_)[item];
    const double Gamma = velocity_scale(p_, params);
    const double rho = flow_density(p_, params, o_.inertia);
    const bool ale = Moving && o_.ale;
    for (int i = 0; i < kRows; ++i) r[i] = 0.0;
    for (int q = 0; q < ref::kQp; ++q) {
      const QpGeometry<double>& g = geo[q];
      const VelocityAt<double> s = velocity_at(u, u + 9, q, g);
      const double tau = supg_time_scale(o_.supg, h, s.v, Gamma);
      W xdot[2];
      if constexpr (Moving)
        if (ale) mesh_velocity(q, udot + kRows, xdot);
      if constexpr (!Mode) add_velocity_rate(q, rho * g.wdetJ, udot, s.K, ale ? xdot : nullptr, r);
      const ConformationAt<NC, double, double> mq(u + kConf, q, g);
      add_conformation_rate<NC>(q, g, tau, s.v, udot + kConf, mq, ale ? xdot : nullptr, r + kConf);
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
    const P Gamma = velocity_scale(p_, params);
    const P Wi = params[p_.Wi], beta = params[p_.beta];
    const P lambda = mode_relaxation_time(P(Wi / Gamma), o_.mode, params);
    const P modulus = mode_modulus(polymer_modulus(p_, params), o_.mode, params);
    const P beta_a = devss_viscosity(o_.devss, beta);
    const P rho = flow_density(p_, params, o_.inertia);
    const T* vx = u;
    const T* vy = u + 9;
    const T* pc = u + 18;         // the first mode's only
    const T* Lc = u + kGradient;  // Lxx[4], Lxy[4], Lyx[4], Lyy[4]
    const T* mc = u + kConf;      // component c at Q1 node k: mc[4 c + k]
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
      const VelocityAt<T> s = velocity_at(vx, vy, q, g);
      G psi[3];
      pressure_basis(g.x, centre, psi);
      T L[2][2];
      interpolated_gradient(Lc, q, L);
      const ConformationAt<NC, T, G> mq(mc, q, g);
      // conformation tensor M (in-plane and zz) and the law's terms there
      const Conformation<T> M = conformation_of<NC>(mq.m, o_.log_conformation);
      const Relaxation<T> k = relaxation(o_.model, NC == 4, M, law);
      if (inadmissible && !(value_of(k.factor) > 0.0)) return {StatusCode::InvalidState, inadmissible};
      const Conformation<T> tp = polymer_stress(M, k, modulus);

      if constexpr (Mode) {
        // a further mode: its polymer stress in the momentum rows
        add_stress_divergence(g, PlaneStress<T>{tp.xx, tp.xy, tp.yy}, r);
      } else {
        // momentum and continuity with the solvent, DEVSS and polymer stresses
        const PlaneStress<T> visc = viscous_stress(beta, s.K), dv = devss_stress(beta_a, s.K, L);
        const PlaneStress<T> stress{visc.xx + dv.xx + tp.xx, visc.xy + dv.xy + tp.xy, visc.yy + dv.yy + tp.yy};
        T load[2];
        momentum_load(s, o_.inertia, rho, o_.source.get(), g.x, load);
        add_momentum_continuity(q, g, psi, s, load, stress, pressure_at(pc, psi), r);

        // velocity-gradient projection
        add_gradient_projection(q, g.wdetJ, s.K, L, r + 21);
      }

      // conformation transport, SUPG-weighted
      const T inv_lambda = inverse_relaxation_time(o_.model, lambda, L, Gamma, o_.owens);
      const T tau = supg_time_scale(o_.supg, h, s.v, Gamma);
      T R[NC];
      conformation_transport(mq, M, s.v, L, k, inv_lambda, o_.log_conformation, xi, Mode ? nullptr : o_.source.get(),
                             g.x, R);
      add_conformation_rows<NC>(q, g, tau, s.v, R, r + kConf);
    }
    return {};
  }

  const Mesh* mesh_;
  const std::vector<std::array<QpGeometry<double>, ref::kQp>>* geometry_;
  std::vector<int> elements_;
  std::vector<int> dofs_;
  std::vector<double> size_;  // sqrt(element area)
  FlowParameterIndices p_;
  ViscoelasticKernelOptions o_;
};

// A further mode of a multi-mode fluid (the header's comment).
template <int NC, bool Moving = false>
using PolymerModeKernel = ViscoelasticFlowKernel<NC, Moving, true>;

}  // namespace keller
