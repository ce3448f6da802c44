// Reference node positions that are affine in one geometric parameter p: X = X0 + p X1. The
// solid wall's reference mesh depends on its thickness t this way, so kernels that evaluate the
// reference map in the parameter's scalar type get dF/dt exactly.
#pragma once

#include <array>
#include <vector>

#include "core/Mesh.hpp"

namespace keller {

struct AffineReference {
  std::vector<std::array<double, 2>> base, slope;  // per mesh node
  int parameter = -1;                              // index of p, or -1: X = X0
  template <class P>
  void element(const Mesh& mesh, int e, const P* params, P (&xy)[9][2]) const {
    const auto& el = mesh.element(e);
    for (int a = 0; a < 9; ++a)
      for (int i = 0; i < 2; ++i)
        xy[a][i] = parameter >= 0 ? P(base[el[a]][i] + params[parameter] * slope[el[a]][i]) : P(base[el[a]][i]);
  }
  // Reference position of a node at parameter values `params`.
  std::array<double, 2> at(int node, const double* params) const {
    const double p = parameter >= 0 ? params[parameter] : 0.0;
    return {base[node][0] + p * slope[node][0], base[node][1] + p * slope[node][1]};
  }
};

}  // namespace keller
