// The Floquet multipliers of periodic orbits for the orbit continuation (continuation/orbits), by
// stability/FloquetMultipliers: where the two folders meet.
#pragma once

#include "continuation/orbits/OrbitContinuation.hpp"
#include "stability/FloquetMultipliers.hpp"

namespace keller {

class FloquetAnalysis final : public OrbitMultipliers {
 public:
  explicit FloquetAnalysis(FloquetOptions options = {}) : options_(options) {}
  Status compute(int n, const std::function<Status(const Vector&, Vector&)>& M,
                 std::vector<std::complex<double>>& values, int& trivial,
                 std::vector<Eigen::VectorXcd>* vectors) override;
  // Of the last compute.
  const FloquetResult& last() const { return last_; }

 private:
  FloquetOptions options_;
  FloquetResult last_;
};

}  // namespace keller
