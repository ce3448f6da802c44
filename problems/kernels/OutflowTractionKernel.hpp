// Boundary kernel of a fully developed outflow for viscoelastic fluids. The momentum equation
// in divergence form has the traction term - int phi . (T n) ds on the boundary; for fully
// developed flow with the pressure datum P = 0 there, T n reduces to the polymer stress tau_p n
// (velocity derivatives along the flow vanish, and the DEVSS term with them). Adding
//   - int phi_a (tau_p(M) n) ds
// with the edge's own outward normal n to the momentum rows makes the normal natural condition
// read -P + 2 beta dv_n/dn = 0, i.e. P = 0 for fully developed flow, as for a Newtonian fluid,
// whichever way the outflow faces. (The tangential velocity is imposed on the outflow, which
// runs along x or y, so only the normal component's rows matter there.)
//
// A law with a second normal stress difference in shear (Giesekus; PTT, whose slip xi gives it
// one) has a fully developed pressure that varies across the channel, P = tau_tt + p0(x) (t the
// tangent: the cross-stream momentum balance), so P = 0 cannot hold on the whole outflow: for
// these laws tau_p - tau_tt I is added instead, and the condition reads -P + tau_tt = 0, which
// fully developed flow satisfies. (The other laws have tau_tt = 0 in shear and keep the kernel
// as it was, to the last digit.)//
// A multi-mode fluid has one such kernel per mode (options.mode), each with its mode's stress.
//
// Local unknowns: v_x (9), v_y (9) of the element owning the edge (rows), then its conformation
// components (NC x 4 Q1 nodes, conformation or Psi) of the mode.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/AutoDiff.hpp"
#include "core/DofMap.hpp"
#include "core/ElementGeometry.hpp"
#include "core/Mesh.hpp"
#include "core/Status.hpp"
#include "problems/kernels/ConformationTransport.hpp"
#include "problems/kernels/FlowParameters.hpp"
#include "problems/kernels/ViscoelasticFlowKernel.hpp"

namespace keller {

template <int NC>
class OutflowTractionKernel {
 public:
  static constexpr int kRows = 18;
  static constexpr int kSize = 18 + 4 * NC;

  OutflowTractionKernel(const Mesh& mesh, const DofMap& dofs, const std::vector<BoundaryEdge>& edges,
                        FlowParameterIndices p, ViscoelasticKernelOptions o)
      : edges_(edges), p_(p), o_(o), second_difference_(o.model == FluidModel::Giesekus || is_ptt(o.model)) {
    const int fv = dofs.field_index("velocity"), fm = dofs.field_index(o_.mode.field);
    dofs_.resize(edges_.size() * kSize);
    geometry_.resize(edges_.size());
    for (size_t k = 0; k < edges_.size(); ++k) {
      dofs.element_dofs(fv, edges_[k].element, &dofs_[k * kSize]);
      dofs.element_dofs(fm, edges_[k].element, &dofs_[k * kSize + 18]);
      double xy[9][2];
      mesh.element_nodes(edges_[k].element, xy);
      map_edge(xy, edges_[k].edge, geometry_[k]);
    }
  }

  std::string name() const { return "outflow-traction"; }
  int num_items() const { return static_cast<int>(edges_.size()); }
  void item_dofs(int item, int* out) const { std::copy_n(&dofs_[static_cast<size_t>(item) * kSize], kSize, out); }

  template <class T, class P>
  Status evaluate(int item, const T* u, const P* params, T* r) const {
    const ref::Tables& tb = ref::tables();
    const int e = edges_[item].edge;
    const P modulus = mode_modulus(polymer_modulus(p_, params), o_.mode, params);
    const LawConstants<P> law = law_constants(p_.law, params);
    const T* mc = u + 18;
    for (int i = 0; i < kRows; ++i) r[i] = 0.0;
    for (int q = 0; q < ref::kEdgeQp; ++q) {
      const EdgeQpGeometry<double>& g = geometry_[item][q];
      T m[NC];
      for (int c = 0; c < NC; ++c) {
        m[c] = 0.0;
        for (int k = 0; k < 4; ++k) m[c] += tb.edge_N1[e][q][k] * mc[4 * c + k];
      }
      const Conformation<T> M = conformation_of<NC>(m, o_.log_conformation);
      const Conformation<T> tp = polymer_stress(M, relaxation(o_.model, NC == 4, M, law), modulus);
      T txx = tp.xx, txy = tp.xy, tyy = tp.yy;
      if (second_difference_) {
        // tau_tt (t the edge's tangent) is taken off the normal stress: with it the pressure of
        // fully developed flow, P = tau_tt + p0, is P = p0 along the boundary
        const double n0 = g.normal[0], n1 = g.normal[1];
        const T ttt = tp.xx * (n1 * n1) - 2.0 * tp.xy * (n0 * n1) + tp.yy * (n0 * n0);
        txx = txx - ttt;
        tyy = tyy - ttt;
      }
      const T tx = txx * g.normal[0] + txy * g.normal[1], ty = txy * g.normal[0] + tyy * g.normal[1];
      for (int a = 0; a < 9; ++a) {
        const double N = tb.edge_N2[e][q][a] * g.wds;
        r[a] -= N * tx;
        r[9 + a] -= N * ty;
      }
    }
    return {};
  }

 private:
  std::vector<BoundaryEdge> edges_;
  std::vector<int> dofs_;
  std::vector<std::array<EdgeQpGeometry<double>, ref::kEdgeQp>> geometry_;
  FlowParameterIndices p_;
  ViscoelasticKernelOptions o_;
  bool second_difference_;  // the law has a second normal stress difference in shear
};

}  // namespace keller
