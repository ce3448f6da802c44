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
    const Eigen::EigenSolver<Eigen::MatrixXd> es(M, false);
    if (es.info() != Eigen::Success) return {StatusCode::NotConverged, "Floquet: the dense eigenvalue solve failed"};
    for (int i = 0; i < n; ++i) out.multipliers.push_back(es.eigenvalues()[i]);
    std::stable_sort(out.multipliers.begin(), out.multipliers.end(), [](auto a, auto b) {
      const double ma = std::abs(a), mb = std::abs(b);
      return ma != mb ? ma > mb : a.imag() > b.imag();
    });
    if (static_cast<int>(out.multipliers.size()) > options.count) {
      int keep = options.count;  // a conjugate pair is not cut in half
      if (out.multipliers[static_cast<size_t>(keep - 1)].imag() > 0.0) ++keep;
      out.multipliers.resize(static_cast<size_t>(keep));
    }
    out.dense = true;
  } else {
    EigenOptions o;
    o.count = options.count;
    o.tolerance = options.tolerance;
    EigenResult r;
    Status st = largest_eigenvalues(n, monodromy, o, r);
    out.applications = r.solves;
    if (!st.is_ok() && r.pairs.empty()) return st;
    for (const EigenPair& p : r.pairs) out.multipliers.push_back(p.value);
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
