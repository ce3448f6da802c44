// An observer for a run that continues an unfinished branch from its row `row`: the run's start
// is that row, already in the file, so it is not passed on; every later point, and the end, is
// passed on numbered as the rows that follow it.
#pragma once

#include "continuation/Continuation.hpp"

namespace keller {

class ContinuedBranch final : public BranchObserver {
 public:
  ContinuedBranch(BranchObserver& inner, int row) : inner_(inner), row_(row) {}
  void on_start(const std::vector<std::string>& o, const std::vector<std::string>& m) override {
    inner_.on_start(o, m);
  }
  void on_point(const BranchPoint& p) override {
    if (p.index <= 0) return;
    inner_.on_point(shifted(p));
  }
  void on_rejected(double l, double s, const Status& w) override { inner_.on_rejected(l, s, w); }
  void on_note(const std::string& m) override { inner_.on_note(m); }
  void on_finish(const std::string& r, const BranchPoint& last) override { inner_.on_finish(r, shifted(last)); }

 private:
  BranchPoint shifted(BranchPoint p) const {
    if (p.index >= 0) p.index += row_;
    return p;
  }
  BranchObserver& inner_;
  int row_;
};

}  // namespace keller
