// Forwards every point of a curve's branch to another observer after moving the curve's borders to
// it (FoldCurveProblem, HopfCurveProblem: update_borders(U) at each accepted point keeps their
// bordered matrices regular along the curve; their test functions' zeros do not depend on them).
#pragma once

#include <string>
#include <vector>

#include "continuation/Continuation.hpp"

namespace keller {

template <class Curve>
class CurveBorderUpdate final : public BranchObserver {
 public:
  CurveBorderUpdate(Curve& curve, BranchObserver& next) : curve_(curve), next_(next) {}
  void on_start(const std::vector<std::string>& o, const std::vector<std::string>& m) override { next_.on_start(o, m); }
  void on_point(const BranchPoint& p) override {
    // a failure here leaves the borders where they were: still regular near this point
    (void)curve_.update_borders(p.u);
    next_.on_point(p);
  }
  void on_rejected(double lambda, double step, const Status& why) override { next_.on_rejected(lambda, step, why); }
  void on_note(const std::string& m) override { next_.on_note(m); }
  void on_finish(const std::string& r, const BranchPoint& last) override { next_.on_finish(r, last); }

 private:
  Curve& curve_;
  BranchObserver& next_;
};

}  // namespace keller
