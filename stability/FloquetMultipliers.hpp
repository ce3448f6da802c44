// The Floquet multipliers of a periodic orbit: the eigenvalues of largest magnitude of its
// monodromy matrix M, given by its action on a vector (one linearised integration over a period,
// continuation/orbits/ShootingMap), by Arnoldi on the operator, or from M formed column by column
// where the problem is smaller than the Arnoldi basis would be. The trivial multiplier (1 for an
// autonomous flow, along the flow direction) is named, and the orbit's stability counted without it.
#pragma once

#include <complex>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/Status.hpp"
#include "core/Types.hpp"

namespace keller {

struct FloquetOptions {
  int count = 8;  // multipliers wanted, those of largest magnitude
  // Arnoldi: every wanted pair's residual |M x - mu x| (|x| = 1) at most this times max(1, |mu_1|),
  // an absolute accuracy on the scale of the unit circle (not relative to |mu|: the smallest wanted
  // multipliers of a dissipative flow can lie at the linearised passes' own error)
  double tolerance = 1e-10;
  // ... or, for a multiplier at least kFarFromCircle from the unit circle (| |mu| - 1 | >= 1/2), at
  // most circle_share times that distance, on the same scale, where that is larger (0: the tolerance
  // alone). What such a multiplier decides is which side of the circle it lies (stability, and the
  // bifurcation tests, which take the multiplier nearest +1, -1 or the circle), and a Ritz value errs
  // by its residual times its condition number: 1% leaves the side sure up to a condition number of
  // 100 / max(1, |mu_1|).
  // Nearer the circle the tolerance holds: there the condition numbers can be large (near a Hopf point
  // the trivial multiplier's vector and the next one's are nearly parallel; on
  // docs/periodic_orbits.md's FSI problem a Ritz value 0.9884 passed a residual test of 1.2e-4
  // where the multiplier was 0.9765).
  double circle_share = 0.0;
  static constexpr double kFarFromCircle = 0.5;
  // The residual a wanted multiplier mu must reach, on the scale max(1, |mu_1|)
  double allowed_residual(std::complex<double> mu) const;
  bool vectors = false;  // an eigenvector of each multiplier (unit 2-norm)
  // Arnoldi's start: the sum of these vectors' real and imaginary parts (a neighbouring orbit's
  // Ritz vectors, FloquetResult::ritz) plus the fixed pseudo-random vector at 10% of its norm, so
  // that other directions stay in reach. Empty (or of another size): the random vector alone.
  std::vector<Eigen::VectorXcd> start;
};

struct FloquetResult {
  std::vector<std::complex<double>> multipliers;  // by |mu| descending, a conjugate pair together
  std::vector<Eigen::VectorXcd> vectors;          // FloquetOptions::vectors: one per multiplier
  std::vector<Eigen::VectorXcd> ritz;             // Arnoldi: the multipliers' Ritz vectors (a next start)
  int trivial = -1;                               // index of the trivial multiplier (the one nearest 1)
  int unstable = 0;                               // multipliers with |mu| > 1, the trivial one left out
  long applications = 0;                          // of M (linearised passes)
  double seconds = 0.0;
  bool dense = false;  // M was formed column by column
  // "stable", or "unstable (k)" with the count
  std::string stability() const;
};

// The multipliers of the n x n monodromy matrix applied by `monodromy(v, Mv)`. A failed
// application is returned as its status.
Status floquet_multipliers(int n, const std::function<Status(const Vector&, Vector&)>& monodromy,
                           const FloquetOptions& options, FloquetResult& out);

// Which multiplier is trivial, and how many of the others lie outside the unit circle (the
// classification alone, on given multipliers: for tests and for stored values).
void classify_multipliers(FloquetResult& result);

}  // namespace keller
