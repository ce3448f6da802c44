#include "core/Term.hpp"

#include <stdexcept>
#include <vector>

namespace keller {

Status Term::rate(int item, const double* u, const double* udot, double* r) const {
  const int m = local_size(), k = local_rows();
  for (int i = 0; i < k; ++i) r[i] = 0.0;
  if (!has_mass()) return {};
  std::vector<double> B(static_cast<size_t>(k) * m);
  Status st = mass(item, u, B.data());
  if (!st.is_ok()) return st;
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < m; ++j) r[i] += B[static_cast<size_t>(i) * m + j] * udot[j];
  return {};
}

Status Term::residual_with_rate(int item, const double* u, const double* udot, double* r) const {
  Status st = residual(item, u, r);
  if (!st.is_ok() || !has_mass()) return st;
  // one buffer per thread, not an allocation per item of every assembly
  thread_local std::vector<double> time;
  time.resize(static_cast<size_t>(local_rows()));
  st = rate(item, u, udot, time.data());
  for (size_t i = 0; i < time.size(); ++i) r[i] += time[i];
  return st;
}

Status Term::directional_derivative(int, const double*, int, const double* const*, const double* const*,
                                    double*) const {
  throw std::logic_error("term '" + name() + "' offers no exact directional derivatives");
}

}  // namespace keller
