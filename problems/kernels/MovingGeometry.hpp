// The geometry of an element of a moving mesh, whose node positions are unknowns: gathered from
// the element's local position unknowns (x of nodes 0..8, then y of nodes 0..8), mapped to
// Gauss-point geometry in the unknowns' scalar type (so the Jacobian holds the shape
// derivatives), and the element size sqrt(area) the SUPG time scale uses.
#pragma once

#include <array>
#include <cmath>

#include "core/ElementGeometry.hpp"
#include "core/ReferenceElement.hpp"

namespace keller {

template <class T>
void gather_positions(const T* x, T (&xy)[9][2]) {
  for (int a = 0; a < 9; ++a) {
    xy[a][0] = x[a];
    xy[a][1] = x[9 + a];
  }
}

// False for an inverted or degenerate element (det J <= 0 at a Gauss point).
template <class T>
bool moving_geometry(const T* x, T (&xy)[9][2], std::array<QpGeometry<T>, ref::kQp>& geo) {
  gather_positions(x, xy);
  return map_element(xy, geo);
}

// sqrt of the element's area, the int dA of its Gauss-point geometry.
template <class G>
G element_size(const std::array<QpGeometry<G>, ref::kQp>& geo) {
  using std::sqrt;
  G area = 0.0;
  for (const auto& g : geo) area += g.wdetJ;
  return G(sqrt(area));
}

}  // namespace keller
