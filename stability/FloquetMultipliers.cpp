#include "stability/FloquetMultipliers.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>

#include "stability/EigenSolver.hpp"

namespace keller {

std::string FloquetResult::stability() const {
  return unstable == 0 ? std::string("stable") : fmt::format("unstable ({})", unstable);
}

void classify_multipliers(FloquetResult& r) {
  r.trivial = -1;
  r.unstable = 0;
  double nearest = 0.0;
  for (size_t i = 0; i < r.multipliers.size(); ++i) {
    const double d = std::abs(r.multipliers[i] - 1.0);
    if (r.trivial < 0 || d < nearest) {
      r.trivial = static_cast<int>(i);
      nearest = d;
    }
  }
  for (size_t i = 0; i < r.multipliers.size(); ++i)
    if (static_cast<int>(i) != r.trivial && std::abs(r.multipliers[i]) > 1.0) ++r.unstable;
}

Status floquet_multipliers(int n, const std::function<Status(const Vector&, Vector&)>& monodromy,
                           const FloquetOptions& options, FloquetResult& out) {
  const auto t0 = std::chrono::steady_clock::now();
  out = FloquetResult{};
  const int basis = std::max(2 * options.count + 1, 20);
  if (n <= basis) {
    // M column by column: no more applications than an Arnoldi basis would take
    Eigen::MatrixXd M(n, n);
    Vector e = Vector::Zero(n), column;
    for (int j = 0; j < n; ++j) {
      e[j] = 1.0;
      Status st = monodromy(e, column);
      ++out.applications;
      if (!st.is_ok()) return st;
      M.col(j) = column;
      e[j] = 0.0;
    }
    const Eigen::EigenSolver<Eigen::MatrixXd> es(M, options.vectors);
    if (es.info() != Eigen::Success) return {StatusCode::NotConverged, "Floquet: the dense eigenvalue solve failed"};
    std::vector<int> order(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) order[static_cast<size_t>(i)] = i;
    const auto& values = es.eigenvalues();
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
      const double ma = std::abs(values[a]), mb = std::abs(values[b]);
      return ma != mb ? ma > mb : values[a].imag() > values[b].imag();
    });
    int keep = std::min(n, options.count);
    if (keep < n && values[order[static_cast<size_t>(keep - 1)]].imag() > 0.0) ++keep;  // a pair stays whole
    for (int k = 0; k < keep; ++k) {
      const int i = order[static_cast<size_t>(k)];
      out.multipliers.push_back(values[i]);
      if (options.vectors) out.vectors.push_back(es.eigenvectors().col(i).normalized());
    }
    out.dense = true;
  } else {
    EigenOptions o;
    o.count = options.count;
    o.tolerance = options.tolerance;
    o.vectors = options.vectors;
    EigenResult r;
    Status st = largest_eigenvalues(n, monodromy, o, r);
    out.applications = r.solves;
    if (!st.is_ok() && r.pairs.empty()) return st;
    for (const EigenPair& p : r.pairs) {
      out.multipliers.push_back(p.value);
      if (options.vectors) out.vectors.push_back(p.vector);
    }
    if (!st.is_ok()) {
      classify_multipliers(out);
      return st;
    }
  }
  classify_multipliers(out);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return {};
}

}  // namespace keller
