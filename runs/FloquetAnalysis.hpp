// The Floquet multipliers of periodic orbits for the orbit continuation (continuation/orbits), by
// stability/FloquetMultipliers: where the two folders meet.
#pragma once

#include "continuation/orbits/OrbitContinuation.hpp"
#include "stability/FloquetMultipliers.hpp"

namespace keller {

class FloquetAnalysis final : public OrbitMultipliers {
 public:
  explicit FloquetAnalysis(FloquetOptions options = {}) : options_(options) {}
  // The analysis of an orbit branch whose rows store `multipliers` ([orbit] multipliers): that many
  // are computed, and at least kLeast (a period doubling's switch needs the one nearest -1 besides
  // the trivial one).
  static constexpr int kLeast = 2;
  static FloquetAnalysis for_branch(int multipliers);
  int count() const { return options_.count; }
  Status compute(int n, const std::function<Status(const Vector&, Vector&)>& M,
                 std::vector<std::complex<double>>& values, int& trivial, std::vector<Eigen::VectorXcd>* vectors,
                 MultiplierAccuracy accuracy) override;
  // Of the last compute.
  const FloquetResult& last() const { return last_; }

 private:
  FloquetOptions options_;
  FloquetResult last_;
};

}  // namespace keller
