// One line per point on the terminal while a branch is traced: step, kind, parameter, key
// observables, corrector iterations, next step size, elapsed time; rejected steps and notes.
#pragma once

#include <string>
#include <vector>

#include "continuation/Continuation.hpp"

namespace keller {

class ProgressPrinter final : public BranchObserver {
 public:
  // Shows the observables named in `first` (a curve's other parameter), then the first
  // `observables` others (all if fewer).
  ProgressPrinter(std::string parameter, int observables = 3, std::vector<std::string> first = {});
  void on_start(const std::vector<std::string>& observable_names,
                const std::vector<std::string>& monitor_names) override;
  void on_point(const BranchPoint& p) override;
  void on_rejected(double lambda, double step, const Status& why) override;
  void on_note(const std::string& message) override;
  void on_finish(const std::string& reason, const BranchPoint& last) override;

 private:
  std::string parameter_;
  int shown_;
  std::vector<std::string> first_;
  std::vector<size_t> columns_;  // the observables shown, by index
};

// Forwards every call to several observers (file, printer, ...).
class ObserverList final : public BranchObserver {
 public:
  explicit ObserverList(std::vector<BranchObserver*> observers) : observers_(std::move(observers)) {}
  void on_start(const std::vector<std::string>& o, const std::vector<std::string>& m) override {
    for (auto* x : observers_) x->on_start(o, m);
  }
  void on_point(const BranchPoint& p) override {
    for (auto* x : observers_) x->on_point(p);
  }
  void on_rejected(double l, double s, const Status& w) override {
    for (auto* x : observers_) x->on_rejected(l, s, w);
  }
  void on_note(const std::string& m) override {
    for (auto* x : observers_) x->on_note(m);
  }
  void on_finish(const std::string& r, const BranchPoint& l) override {
    for (auto* x : observers_) x->on_finish(r, l);
  }

 private:
  std::vector<BranchObserver*> observers_;
};

}  // namespace keller
