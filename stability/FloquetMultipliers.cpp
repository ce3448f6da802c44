#include "stability/FloquetMultipliers.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>

namespace keller {

namespace {

// A fixed start (runs are reproducible): a linear congruential sequence in [-1, 1].
Vector fixed_start(int n) {
  Vector v(n);
  std::uint64_t x = 88172645463325252ull;
  for (int i = 0; i < n; ++i) {
    x = x * 6364136223846793005ull + 1442695040888963407ull;
    v[i] = static_cast<double>(x >> 11) / static_cast<double>(1ull << 53) * 2.0 - 1.0;
  }
  return v / v.norm();
}

struct Ritz {
  std::complex<double> value;
  Eigen::VectorXcd y;  // unit eigenvector of H
  double residual = 0.0;
};

// H's eigenpairs by |value| descending (of a pair, the one with positive imaginary part first), and
// each pair's Arnoldi residual |M x - mu x| = beta |y_m| for x = V y.
std::vector<Ritz> ritz_pairs(const Eigen::MatrixXd& H, double beta) {
  const Eigen::EigenSolver<Eigen::MatrixXd> es(H, true);
  std::vector<Ritz> r(static_cast<size_t>(H.rows()));
  for (int i = 0; i < H.rows(); ++i) {
    Ritz& p = r[static_cast<size_t>(i)];
    p.value = es.eigenvalues()[i];
    p.y = es.eigenvectors().col(i).normalized();
    p.residual = beta * std::abs(p.y[H.rows() - 1]);
  }
  std::stable_sort(r.begin(), r.end(), [](const Ritz& a, const Ritz& b) {
    const double ma = std::abs(a.value), mb = std::abs(b.value);
    return ma != mb ? ma > mb : a.value.imag() > b.value.imag();
  });
  return r;
}

// The `count` multipliers of largest magnitude by Arnoldi on M with explicit restarts. ARPACK's
// test (a residual below tolerance |mu| for every wanted mu) cannot be met by multipliers of
// magnitude near the passes' own error, and a dissipative flow has many: here every wanted pair's
// residual is measured against max(1, |mu_1|), the scale that decides stability.
Status krylov_multipliers(int n, const std::function<Status(const Vector&, Vector&)>& monodromy,
                          const FloquetOptions& options, FloquetResult& out) {
  const int m = std::min(n - 1, std::max(3 * options.count, 30));
  constexpr int kRestarts = 20;
  Eigen::MatrixXd V(n, m + 1), H = Eigen::MatrixXd::Zero(m + 1, m);
  Vector start = fixed_start(n), w;
  Vector warm = Vector::Zero(n);
  for (const Eigen::VectorXcd& x : options.start)
    if (x.size() == n) warm += x.real() + x.imag();
  if (warm.norm() > 0.0) start = (warm / warm.norm() + 0.1 * start).normalized();
  double worst = 0.0;
  std::vector<Ritz> ritz;
  int keep = 0, size = 0;
  for (int restart = 0; restart <= kRestarts; ++restart) {
    V.col(0) = start;
    H.setZero();
    bool done = false;
    for (int j = 0; j < m && !done; ++j) {
      Status st = monodromy(V.col(j), w);
      ++out.applications;
      if (!st.is_ok()) return st;
      for (int pass = 0; pass < 2; ++pass)  // Gram-Schmidt, twice (Kahan: twice is enough)
        for (int i = 0; i <= j; ++i) {
          const double h = V.col(i).dot(w);
          H(i, j) += h;
          w -= h * V.col(i);
        }
      const double beta = w.norm();
      H(j + 1, j) = beta;
      const bool invariant = beta <= 1e-14 * std::max(H.col(j).norm(), 1e-300);
      size = j + 1;
      if (size > options.count || invariant || j + 1 == m) {
        ritz = ritz_pairs(H.topLeftCorner(size, size), invariant ? 0.0 : beta);
        keep = std::min(options.count, size);
        if (keep < size && ritz[static_cast<size_t>(keep - 1)].value.imag() > 0.0) ++keep;  // a pair stays whole
        const double scale = std::max(1.0, std::abs(ritz[0].value));
        worst = 0.0;  // the largest residual as a share of what its multiplier allows
        for (int k = 0; k < keep; ++k) {
          const Ritz& r = ritz[static_cast<size_t>(k)];
          worst = std::max(worst, r.residual / (scale * options.allowed_residual(r.value)));
        }
        done = invariant || worst <= 1.0;
      }
      if (!done && j + 1 < m) V.col(j + 1) = w / beta;
    }
    if (done || restart == kRestarts) break;
    // restart from the wanted Ritz vectors: the directions the next basis must refine
    start.setZero();
    for (int k = 0; k < keep; ++k) {
      const Eigen::VectorXcd x = V.leftCols(size).cast<std::complex<double>>() * ritz[static_cast<size_t>(k)].y;
      start += x.real() + x.imag();
    }
    start /= start.norm();
  }
  for (int k = 0; k < keep; ++k) {
    out.multipliers.push_back(ritz[static_cast<size_t>(k)].value);
    out.ritz.push_back((V.leftCols(size).cast<std::complex<double>>() * ritz[static_cast<size_t>(k)].y).normalized());
    if (options.vectors) out.vectors.push_back(out.ritz.back());
  }
  if (worst > 1.0)
    return {StatusCode::NotConverged,
            fmt::format("Floquet: after {} applications of M a wanted multiplier's residual is {:.2e} times what it "
                        "must reach (tolerance {:.1e} of max(1, |mu_1|), circle share {:.1e})",
                        out.applications, worst, options.tolerance, options.circle_share)};
  return {};
}

}  // namespace

double FloquetOptions::allowed_residual(std::complex<double> mu) const {
  const double distance = std::abs(std::abs(mu) - 1.0);
  const double allowed = distance >= kFarFromCircle ? std::max(tolerance, circle_share * distance) : tolerance;
  return std::max(allowed, 0.0);  // a negative tolerance is never met, as before the share
}

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
    const Status st = krylov_multipliers(n, monodromy, options, out);
    if (!st.is_ok() && out.multipliers.empty()) return st;
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
