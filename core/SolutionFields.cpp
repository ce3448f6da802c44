#include "core/SolutionFields.hpp"

#include <limits>

namespace keller {

SolutionFields extract_fields(const Mesh& mesh, const DofMap& dofs, const Vector& u) {
  SolutionFields out;
  out.mesh = &mesh;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int f = 0; f < dofs.num_fields(); ++f) {
    const FieldSpec& fs = dofs.field(f);
    const int nc = dofs.num_components(f);
    if (fs.basis == Basis::P1Disc) {
      ElementField ef{fs.name,
                      to_string(fs.basis),
                      fs.components,
                      fs.groups,
                      Eigen::MatrixXd::Constant(mesh.num_elements(), 3 * nc, nan),
                      Eigen::MatrixXd::Constant(mesh.num_elements(), nc, nan)};
      for (int e = 0; e < mesh.num_elements(); ++e) {
        if (!dofs.on_element(f, e)) continue;
        for (int c = 0; c < nc; ++c) {
          for (int k = 0; k < 3; ++k) ef.coefficients(e, 3 * c + k) = u[dofs.element_dof(f, e, k, c)];
          ef.centre_values(e, c) = ef.coefficients(e, 3 * c);
        }
      }
      out.element.push_back(std::move(ef));
      continue;
    }
    NodalField nf{fs.name, to_string(fs.basis), fs.components, fs.groups,
                  Eigen::MatrixXd::Constant(mesh.num_nodes(), nc, nan)};
    for (int e = 0; e < mesh.num_elements(); ++e) {
      if (!dofs.on_element(f, e)) continue;
      const auto& el = mesh.element(e);
      for (int c = 0; c < nc; ++c) {
        if (fs.basis == Basis::Q2) {
          for (int a = 0; a < 9; ++a) nf.values(el[a], c) = u[dofs.node_dof(f, el[a], c)];
        } else {
          double v[4];
          for (int k = 0; k < 4; ++k) v[k] = u[dofs.node_dof(f, el[ref::q1_node[k]], c)];
          for (int a = 0; a < 9; ++a) {
            double N[4], dN[4][2];
            ref::q1_shape(ref::node_s(a), ref::node_t(a), N, dN);
            nf.values(el[a], c) = N[0] * v[0] + N[1] * v[1] + N[2] * v[2] + N[3] * v[3];
          }
        }
      }
    }
    out.nodal.push_back(std::move(nf));
  }
  return out;
}

}  // namespace keller
