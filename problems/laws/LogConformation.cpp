#include "problems/laws/LogConformation.hpp"

#include <stdexcept>

namespace keller {

Sym2<double> sym_log(const Sym2<double>& m) {
  const double a = 0.5 * (m.xx + m.yy), d = 0.5 * (m.xx - m.yy);
  const double r = std::sqrt(d * d + m.xy * m.xy);
  // the smaller eigenvalue as det / l2: a - r loses its digits when M is far from isotropic (M_xx
  // = 5902, M_yy = 0.016 in a Giesekus fluid's planar extension: 4e-11 relative in a - r)
  const double l2 = a + r, l1 = (m.xx * m.yy - m.xy * m.xy) / l2;
  if (!(l1 > 0)) throw std::domain_error("sym_log: matrix is not positive definite");
  // log M = 1/2 (log l1 + log l2) I + (log l2 - log l1) / (l2 - l1) N, the divided difference
  // tending to 1 / a as r -> 0
  const double mean = 0.5 * (std::log(l1) + std::log(l2));
  const double z = r / a;
  const double dd = z < 1e-4 ? (1.0 + z * z / 3.0) / a : std::log(l2 / l1) / (2.0 * r);
  return {mean + dd * d, dd * m.xy, mean - dd * d};
}

}  // namespace keller
