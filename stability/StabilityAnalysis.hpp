// Linear stability of each point of a branch: the eigenvalues of J phi = sigma B phi nearest one
// or more shifts (EigenSolver), merged, as columns of the branch table (sigma1_re, sigma1_im, ...
// by real part ascending), the number of unstable eigenvalues (Re sigma < 0, since B du/dt = -F,
// and not neutral: |Re sigma| above neutral_tolerance x max(1, |sigma|))
// among those computed, and the critical eigenvalue (nearest the imaginary axis) with its
// eigenvector, so that the continuation engine detects and locates where the count changes.
// Eigenvalues far from every shift are not computed: a count is "among the eigenvalues nearest
// the shifts", as in every shift-invert monitor; where the farthest of those computed are
// unstable, or an unstable mode of the last analysis is missing from the set, more are computed
// (SpectrumEdge), so that an unstable eigenvalue moving away from the shift stays counted. A
// multiple eigenvalue (the modes of a symmetric domain) counts as often as it is found.
// A problem without dynamics (B = 0: no row carries a time derivative) has no finite
// eigenvalue: count 0, columns NaN.
#pragma once

#include <complex>
#include <string>
#include <vector>

#include "core/PointAnalysis.hpp"
#include "core/Scene.hpp"
#include "stability/EigenSolver.hpp"

namespace keller {

struct StabilityOptions {
  bool enabled = false;
  int count = 6;                                     // eigenvalues per shift (and columns)
  std::vector<std::complex<double>> shifts = {0.0};  // shift-invert points
  int every = 1;                                     // analyse every N-th accepted point
  double residual_tolerance = 1e-8;                  // relative eigen-residual that is accepted
  int ncv = 0;                                       // Arnoldi basis size (0: EigenSolver's default)
  double arpack_tolerance = 1e-10;                   // ARPACK's relative accuracy of the Ritz values
  double neutral_tolerance = 1e-8;                   // |Re sigma| <= this x max(1,|sigma|): neutral
  bool warm_start = true;                            // Arnoldi starts from the eigenvectors of the last analysed point
  static void declare(SceneSchema& schema);
  static StabilityOptions from_scene(const Scene& scene);
  // Throws SceneError where the problem cannot be analysed as the scene asks: it has no
  // time-dependent form (naming stability.enabled), or count does not fit its n unknowns (naming
  // stability.count: ARPACK finds at most n - 2 eigenvalues).
  void check_problem(const Scene& scene, Problem& problem) const;
};

class StabilityAnalysis final : public PointAnalysis {
 public:
  explicit StabilityAnalysis(StabilityOptions options, SparseLUOptions lu = {});
  std::vector<std::string> column_names() const override;
  std::string count_name() const override { return "unstable eigenvalues"; }
  Status analyse(Problem& problem, const Vector& u, PointAnalysisResult& out,
                 SparseLU* factorised_j = nullptr) override;
  int every() const override { return options_.every; }
  // a real shift at 0 solves with J's factorisation
  bool uses_j_factorisation() const override;
  // Doubles the eigenvalues computed at every shift, up to the cap; false where all are at it.
  bool widen() override;

  // The merged spectrum of the last analyse() (Re ascending), with eigenvectors.
  const std::vector<EigenPair>& spectrum() const { return spectrum_; }
  // Totals over all calls (for the cost report).
  double seconds() const { return seconds_; }
  long factorisations() const { return factorisations_; }
  long solves() const { return solves_; }

 private:
  StabilityOptions options_;
  EigenSolver solver_;
  SparseMatrix J_, B_;
  Vector F_;
  std::vector<EigenPair> spectrum_;
  std::vector<std::vector<Eigen::VectorXcd>> previous_;  // per shift: the last point's eigenvectors
  std::vector<int> counts_;  // per shift: eigenvalues computed (count, grown where the set's edge was unstable)
  // the eigenvectors of the last analysis's unstable eigenvalues: each must be in the next set (SpectrumEdge)
  std::vector<Eigen::VectorXcd> previous_unstable_;
  int cap_ = 0;             // the most counts_ can grow to (set by the first analysis)
  double last_spread_ = 0;  // the last set's largest |sigma - first shift| (SpectrumEdge: shift_move)
  // the grown set's cap: kGrowthCap times count, at least kGrowthFloor (and at most n - 2)
  static constexpr int kGrowthCap = 8, kGrowthFloor = 32;
  double seconds_ = 0;
  long factorisations_ = 0, solves_ = 0;
};

}  // namespace keller
