// Element kernel of steady incompressible Newtonian flow on one 9-node element: Q2 velocity,
// P1-discontinuous pressure in physical coordinates, the momentum and continuity terms of
// Momentum.hpp with the stress T = -P I + beta (K + K^T). On a fixed mesh the Gauss-point
// geometry is cached; on a moving mesh (Moving = true) the element's node positions are
// unknowns too and the geometry is computed from them in the unknowns' scalar type
// (MovingGeometry.hpp), which puts the shape derivatives into the Jacobian.
// The traction boundary term is absent: on the outflow it is the natural condition
// T_xx = 0 (-P + 2 beta dv_x/dx = 0), i.e. P = 0 for fully developed flow.
//
// Local unknowns (21): v_x at nodes 0..8, v_y at nodes 0..8, P coefficients 0..2; on a moving
// mesh then x and y of nodes 0..8 (39), whose rows this kernel does not write (kRows = 21).
// Time-dependent form: (Re/Gamma) dv/dt adds (Re/Gamma) int phi_a dv/dt to the velocity rows
// (rate(); the mass block from it), dv/dt the rate at a fixed point of space: on a moving mesh
// with `ale` the nodal rate minus xdot . grad v (the nodes move at the rates xdot of the position
// unknowns); continuity has no time derivative. With Re = 0 the mass matrix is zero.
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
#include "problems/kernels/FlowParameters.hpp"
#include "problems/kernels/FlowSource.hpp"
#include "problems/kernels/Momentum.hpp"
#include "problems/kernels/MovingGeometry.hpp"

namespace keller {

template <bool Moving = false>
class NewtonianFlowKernel {
 public:
  static constexpr int kRows = 21;
  static constexpr int kSize = Moving ? 39 : 21;

  // elements: the fluid elements; geometry: their cached Gauss-point geometry (same order);
  // params: Re (with inertia), Gamma (-1: 1) and beta (-1: 1); source: a body force, or null;
  // ale: the time derivative at a fixed point of a moving mesh (Moving only).
  NewtonianFlowKernel(const Mesh& mesh, const DofMap& dofs, std::vector<int> elements,
                      const std::vector<std::array<QpGeometry<double>, ref::kQp>>* geometry,
                      FlowParameterIndices params, bool inertia, std::shared_ptr<const FlowSource> source = nullptr,
                      bool ale = false)
      : mesh_(&mesh),
        geometry_(geometry),
        elements_(std::move(elements)),
        p_(params),
        inertia_(inertia),
        ale_(Moving && ale),
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
  void item_dofs(int item, int* out) const { std::copy_n(&dofs_[static_cast<size_t>(item) * kSize], kSize, out); }

  // The time terms r = B(u) udot of the rows (udot: the rates of the local unknowns).
  template <class W>
  Status rate(int item, const double* u, const W* udot, const double* params, W* r) const {
    const double rho = flow_density(p_, params, inertia_);
    for (int i = 0; i < kRows; ++i) r[i] = 0.0;
    std::array<QpGeometry<double>, ref::kQp> moved;
    if constexpr (Moving) {
      double xy[9][2];
      if (!moving_geometry(u + kRows, xy, moved)) return inverted(item);
    }
    const auto& geo = Moving ? moved : (*geometry_)[item];
    for (int q = 0; q < ref::kQp; ++q) {
      const VelocityAt<double> s = velocity_at(u, u + 9, q, geo[q]);
      W xdot[2];
      if constexpr (Moving)
        if (ale_) mesh_velocity(q, udot + kRows, xdot);
      add_velocity_rate(q, rho * geo[q].wdetJ, udot, s.K, ale_ ? xdot : nullptr, r);
    }
    return {};
  }

  // The residual and the time terms together, r = F + B(u) udot: the moving element's geometry and
  // each Gauss point's velocity gradient computed once for both (KernelTerm::residual_with_rate).
  Status evaluate_with_rate(int item, const double* u, const double* udot, const double* params, double* r) const {
    const double rho = flow_density(p_, params, inertia_);
    auto time_terms = [&](int q, const QpGeometry<double>& g, const VelocityAt<double>& s) {
      double xdot[2] = {0.0, 0.0};
      if constexpr (Moving)
        if (ale_) mesh_velocity(q, udot + kRows, xdot);
      add_velocity_rate(q, rho * g.wdetJ, udot, s.K, ale_ ? xdot : nullptr, r);
    };
    return on_geometry(item, u, r, [&](const auto& geo, const auto& centre) {
      return evaluate_on(u, params, r, geo, centre, time_terms);
    });
  }

  template <class T, class P>
  Status evaluate(int item, const T* u, const P* params, T* r) const {
    return on_geometry(item, u, r,
                       [&](const auto& geo, const auto& centre) { return evaluate_on(u, params, r, geo, centre); });
  }

 private:
  // on(geo, centre) with the element's Gauss-point geometry and centre node: on a moving mesh
  // computed from the position unknowns in their scalar T (an inverted element: r zero and a
  // status), on a fixed one the cached geometry.
  template <class T, class On>
  Status on_geometry(int item, const T* u, T* r, On on) const {
    if constexpr (Moving) {
      T xy[9][2];
      std::array<QpGeometry<T>, ref::kQp> geo;
      if (!moving_geometry(u + kRows, xy, geo)) {
        for (int i = 0; i < kRows; ++i) r[i] = 0.0;
        return inverted(item);
      }
      return on(geo, xy[4]);
    } else {
      const auto& c = mesh_->node(mesh_->element(elements_[item])[4]);
      const double centre[2] = {c[0], c[1]};
      return on((*geometry_)[item], centre);
    }
  }

  Status inverted(int item) const {
    return {StatusCode::InvalidState, "fluid element " + std::to_string(elements_[item]) + " is inverted (det J <= 0)"};
  }

  // The residual on an element with Gauss-point geometry geo (scalar G: double on a fixed mesh,
  // T on a moving one) and centre node position centre; at each Gauss point q, after its
  // residual, also(q, geometry, velocity) (evaluate_with_rate's time terms).
  struct Nothing {
    template <class... A>
    void operator()(const A&...) const {}
  };
  template <class T, class P, class G, class Also = Nothing>
  Status evaluate_on(const T* u, const P* params, T* r, const std::array<QpGeometry<G>, ref::kQp>& geo,
                     const G (&centre)[2], Also also = {}) const {
    const P beta = solvent_viscosity(p_, params);
    const P rho = flow_density(p_, params, inertia_);
    const T* vx = u;
    const T* vy = u + 9;
    const T* pc = u + 18;
    for (int i = 0; i < kRows; ++i) r[i] = 0.0;
    for (int q = 0; q < ref::kQp; ++q) {
      const QpGeometry<G>& g = geo[q];
      const VelocityAt<T> s = velocity_at(vx, vy, q, g);
      G psi[3];
      pressure_basis(g.x, centre, psi);
      T load[2];
      momentum_load(s, inertia_, rho, force_.get(), g.x, load);
      add_momentum_continuity(q, g, psi, s, load, viscous_stress(beta, s.K), pressure_at(pc, psi), r);
      also(q, g, s);
    }
    return {};
  }

  const Mesh* mesh_;
  const std::vector<std::array<QpGeometry<double>, ref::kQp>>* geometry_;
  std::vector<int> elements_;
  std::vector<int> dofs_;
  FlowParameterIndices p_;
  bool inertia_;
  bool ale_;
  std::shared_ptr<const FlowSource> force_;  // null unless a body force is given
};

}  // namespace keller
