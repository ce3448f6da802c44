#include "core/BorderedJacobian.hpp"

#include <cmath>
#include <limits>
#include <vector>

namespace keller {

SparseMatrix BorderedJacobian::assembled() const {
  const int nk = inner_size(), m = border_size();
  std::vector<Eigen::Triplet<double, int>> t;
  t.reserve(static_cast<size_t>(K.nonZeros()) + 2 * static_cast<size_t>(nk) * m + m * m);
  for (int j = 0; j < K.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(K, j); it; ++it) t.emplace_back(it.row(), j, it.value());
  for (int b = 0; b < m; ++b)
    for (int i = 0; i < nk; ++i) {
      t.emplace_back(i, nk + b, B(i, b));
      t.emplace_back(nk + b, i, C(i, b));
    }
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) t.emplace_back(nk + i, nk + j, D(i, j));
  SparseMatrix A(nk + m, nk + m);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

double BorderedJacobian::rounding_floor(const Vector& u) const {
  const int nk = inner_size(), m = border_size();
  Vector row = B.cwiseAbs() * u.tail(m).cwiseAbs();
  for (int c = 0; c < K.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(K, c); it; ++it) row[it.row()] += std::abs(it.value() * u[c]);
  const Vector border = C.cwiseAbs().transpose() * u.head(nk).cwiseAbs() + D.cwiseAbs() * u.tail(m).cwiseAbs();
  const double largest = std::max(nk ? row.maxCoeff() : 0.0, m ? border.maxCoeff() : 0.0);
  return std::numeric_limits<double>::epsilon() * largest;
}

}  // namespace keller
