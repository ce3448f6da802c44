#include "continuation/ProgressPrinter.hpp"

#include <fmt/format.h>

#include <cstdio>

namespace keller {

ProgressPrinter::ProgressPrinter(std::string parameter, int observables)
    : parameter_(std::move(parameter)), shown_(observables) {}

void ProgressPrinter::on_start(const std::vector<std::string>& observable_names, const std::vector<std::string>&) {
  names_ = observable_names;
  if (static_cast<int>(names_.size()) > shown_) names_.resize(shown_);
  std::string head = fmt::format("  {:>5}  {:<12} {:>14}", "row", "kind", parameter_);
  for (const auto& n : names_) head += fmt::format(" {:>14}", n);
  head += fmt::format(" {:>5} {:>9} {:>10} {:>9}", "iters", "|F|", "next step", "time s");
  fmt::print("{}\n", head);
  std::fflush(stdout);
}

void ProgressPrinter::on_point(const BranchPoint& p) {
  std::string kind = to_string(p.kind);
  if (!p.label.empty() && p.kind != PointKind::Requested) kind += " " + p.label;
  std::string line = fmt::format("  {:>5}  {:<12} {:>14.8g}", p.index, kind, p.lambda);
  for (size_t i = 0; i < names_.size() && i < p.observables.size(); ++i)
    line += fmt::format(" {:>14.7g}", p.observables[i]);
  line += fmt::format(" {:>5} {:>9.2e} {:>10.3e} {:>9.2f}", p.iterations, p.residual, p.step, p.seconds);
  fmt::print("{}\n", line);
  std::fflush(stdout);
}

void ProgressPrinter::on_rejected(double lambda, double step, const Status& why) {
  fmt::print("         step rejected near {} = {:.8g} (step {:.3e}): {}; halving\n", parameter_, lambda, step,
             why.describe());
  std::fflush(stdout);
}

void ProgressPrinter::on_note(const std::string& message) {
  fmt::print("         note: {}\n", message);
  std::fflush(stdout);
}

void ProgressPrinter::on_finish(const std::string& reason, const BranchPoint& last) {
  fmt::print("branch ended: {} (last row {}, {} = {:.10g})\n", reason, last.index, parameter_, last.lambda);
  std::fflush(stdout);
}

}  // namespace keller
