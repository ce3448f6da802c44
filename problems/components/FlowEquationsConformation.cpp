// FlowEquations' view of the conformation of a solution: each mode's eigenvalues node by node
// (min_m1's places and gradient, the extremes), the summed polymer stress at a point, and the
// output fields of the eigenvalues and of M. The rest of the class is FlowEquations.cpp.
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "problems/components/FlowEquations.hpp"
#include "problems/laws/LogConformation.hpp"

namespace keller {

std::array<double, 3> FlowEquations::node_eigenvalues(const Vector& u, int n, size_t mode) const {
  const DofMap& dofs = *dofs_;
  const int fm = dofs.field_index(modes_[mode].field);
  const int nc = options_.conformation_components();
  const double b = law_constants(index_.law, params_->values()).b;
  double c[4] = {0, 0, 0, 0};
  for (int k = 0; k < nc; ++k) c[k] = u[dofs.node_dof(fm, n, k)];
  double xx = c[0], xy = c[1], yy = c[2], zz = 1.0;
  if (options_.log_conformation) {
    const Sym2<double> M = sym_exp(Sym2<double>{c[0], c[1], c[2]});
    xx = M.xx;
    xy = M.xy;
    yy = M.yy;
    if (nc == 4) zz = std::exp(c[3]);
  } else if (nc == 4) {
    zz = c[3];
  }
  if (options_.model == FluidModel::FeneP && nc == 3) zz = 1.0 / peterlin_eliminated(xx, yy, b);
  const double a = 0.5 * (xx + yy), r = std::hypot(0.5 * (xx - yy), xy);
  std::array<double, 3> e = {a - r, a + r, zz};
  std::sort(e.begin(), e.end());
  return e;
}

void FlowEquations::conformation_eigenvalues(const Vector& u, std::vector<int>& nodes,
                                             std::vector<std::array<double, 3>>& eig) const {
  nodes.clear();
  eig.clear();
  if (!options_.viscoelastic()) return;
  const int fm = dofs_->field_index("conformation");
  for (size_t mode = 0; mode < modes_.size(); ++mode)
    for (int n = 0; n < mesh_->num_nodes(); ++n) {
      if (dofs_->node_dof(fm, n, 0) < 0) continue;
      nodes.push_back(n);
      eig.push_back(node_eigenvalues(u, n, mode));
    }
}

void FlowEquations::m1_places(const Vector& u, std::vector<double>& values) const {
  std::vector<int> nodes;
  std::vector<std::array<double, 3>> eig;
  conformation_eigenvalues(u, nodes, eig);
  values.resize(eig.size());
  for (size_t k = 0; k < eig.size(); ++k) values[k] = eig[k][0];
}

void FlowEquations::m1_place_gradient(const Vector& u, int place, Vector& gradient) const {
  if (!options_.viscoelastic()) throw std::logic_error("m1_place_gradient: a Newtonian fluid has no conformation");
  int vertices = 0;
  for (int node = 0; node < mesh_->num_nodes(); ++node)
    if (dofs_->node_dof(dofs_->field_index("conformation"), node, 0) >= 0) ++vertices;
  if (place < 0 || vertices == 0 || place >= vertices * static_cast<int>(modes_.size()))
    throw std::out_of_range("min_m1 has no place " + std::to_string(place));
  const size_t mode = static_cast<size_t>(place / vertices);
  const int fm = dofs_->field_index(modes_[mode].field);
  int n = -1;
  for (int node = 0, k = 0; node < mesh_->num_nodes() && n < 0; ++node)
    if (dofs_->node_dof(fm, node, 0) >= 0 && k++ == place % vertices) n = node;
  gradient = Vector::Zero(u.size());
  Vector w = u;
  for (int c = 0; c < dofs_->num_components(fm); ++c) {
    const int d = dofs_->node_dof(fm, n, c);
    if (d < 0) continue;
    const double h = 1e-6 * std::max(1.0, std::abs(u[d]));
    w[d] = u[d] + h;
    const double hi = node_eigenvalues(w, n, mode)[0];
    w[d] = u[d] - h;
    const double lo = node_eigenvalues(w, n, mode)[0];
    w[d] = u[d];
    gradient[d] = (hi - lo) / (2.0 * h);
  }
}

FlowEquations::ConformationExtremes FlowEquations::conformation_extremes(const Vector& u) const {
  std::vector<int> nodes;
  std::vector<std::array<double, 3>> eig;
  conformation_eigenvalues(u, nodes, eig);
  ConformationExtremes x;
  for (size_t k = 0; k < eig.size(); ++k) {
    if (eig[k][0] < x.min_m1) {
      x.min_m1 = eig[k][0];
      x.min_m1_node = nodes[k];
    }
    x.max_m3 = std::max(x.max_m3, eig[k][2]);
    x.max_trace = std::max(x.max_trace, eig[k][0] + eig[k][1] + eig[k][2]);
  }
  return x;
}

void FlowEquations::add_fields(const Vector& u, SolutionFields& out) const {
  if (!options_.viscoelastic()) return;
  std::vector<int> nodes;
  std::vector<std::array<double, 3>> eig;
  conformation_eigenvalues(u, nodes, eig);
  const int N = mesh_->num_nodes();
  const size_t vertices = nodes.size() / modes_.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const DofMap& dofs = *dofs_;
  for (size_t mode = 0; mode < modes_.size(); ++mode) {
    std::vector<std::array<double, 6>> at(N, {nan, nan, nan, nan, nan, nan});  // m1 m2 m3 Mxx Mxy Myy
    const int fm = dofs.field_index(modes_[mode].field);
    for (size_t k = mode * vertices; k < (mode + 1) * vertices; ++k) {
      const int n = nodes[k];
      double c[3] = {u[dofs.node_dof(fm, n, 0)], u[dofs.node_dof(fm, n, 1)], u[dofs.node_dof(fm, n, 2)]};
      if (options_.log_conformation) {
        const Sym2<double> M = sym_exp(Sym2<double>{c[0], c[1], c[2]});
        c[0] = M.xx;
        c[1] = M.xy;
        c[2] = M.yy;
      }
      at[n] = {eig[k][0], eig[k][1], eig[k][2], c[0], c[1], c[2]};
    }
    // Q1 interpolation from the vertices to every node of each fluid element
    auto q1_field = [&](const std::string& name, std::vector<std::string> comps, int first) {
      NodalField f{name, "Q1", comps, fields_[0].groups,
                   Eigen::MatrixXd::Constant(N, static_cast<long>(comps.size()), nan)};
      for (int e : elements_) {
        const auto& el = mesh_->element(e);
        for (int a = 0; a < 9; ++a) {
          double Nq[4], dN[4][2];
          ref::q1_shape(ref::node_s(a), ref::node_t(a), Nq, dN);
          for (size_t c = 0; c < comps.size(); ++c) {
            double v = 0;
            for (int k = 0; k < 4; ++k) v += Nq[k] * at[el[ref::q1_node[k]]][static_cast<size_t>(first) + c];
            f.values(el[a], static_cast<long>(c)) = v;
          }
        }
      }
      out.nodal.push_back(std::move(f));
    };
    const std::string suffix = mode == 0 ? "" : "_" + options_.modes[mode].name;
    q1_field("conformation_eigenvalues" + suffix, {"m1", "m2", "m3"}, 0);
    if (options_.log_conformation) q1_field("conformation_M" + suffix, {"Mxx", "Mxy", "Myy"}, 3);
  }
}

Conformation<double> FlowEquations::polymer_stress_at(const Vector& u, const double* p, int e,
                                                      const double (&N1)[4]) const {
  Conformation<double> sum{0.0, 0.0, 0.0, 0.0};
  if (!options_.viscoelastic()) return sum;
  const int nc = options_.conformation_components();
  const double modulus = polymer_modulus(index_, p);
  const LawConstants<double> law = law_constants(index_.law, p);
  for (const PolymerMode& mode : modes_) {
    int d[16];
    dofs_->element_dofs(dofs_->field_index(mode.field), e, d);
    double m[4] = {0, 0, 0, 0};
    for (int c = 0; c < nc; ++c)
      for (int k = 0; k < 4; ++k) m[c] += N1[k] * u[d[4 * c + k]];
    const Conformation<double> M =
        nc == 4 ? conformation_of<4>(m, options_.log_conformation) : conformation_of<3>(m, options_.log_conformation);
    const Conformation<double> tp =
        polymer_stress(M, relaxation(options_.model, nc == 4, M, law), mode_modulus(modulus, mode, p));
    sum = {sum.xx + tp.xx, sum.xy + tp.xy, sum.yy + tp.yy, sum.zz + tp.zz};
  }
  return sum;
}

}  // namespace keller
