#include "continuation/output/ProgressPrinter.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>

namespace keller {

ProgressPrinter::ProgressPrinter(std::string parameter, int observables, std::vector<std::string> first)
    : parameter_(std::move(parameter)), shown_(observables), first_(std::move(first)) {}

void ProgressPrinter::on_start(const std::vector<std::string>& observable_names, const std::vector<std::string>&) {
  columns_.clear();
  for (const std::string& name : first_)
    for (size_t i = 0; i < observable_names.size(); ++i)
      if (observable_names[i] == name) columns_.push_back(i);
  const size_t named = columns_.size();
  for (size_t i = 0; i < observable_names.size() && static_cast<int>(columns_.size() - named) < shown_; ++i)
    if (std::find(columns_.begin(), columns_.end(), i) == columns_.end()) columns_.push_back(i);
  std::string head = fmt::format("  {:>5}  {:<12} {:>14}", "row", "kind", parameter_);
  for (size_t i : columns_) head += fmt::format(" {:>14}", observable_names[i]);
  head += fmt::format(" {:>5} {:>9} {:>10} {:>9}", "iters", "|F|", "next step", "time s");
  fmt::print("{}\n", head);
  std::fflush(stdout);
}

void ProgressPrinter::on_point(const BranchPoint& p) {
  std::string kind = to_string(p.kind);
  if (!p.label.empty() && p.kind != PointKind::Requested) kind += " " + p.label;
  std::string line = fmt::format("  {:>5}  {:<12} {:>14.8g}", p.index, kind, p.lambda);
  for (size_t i : columns_)
    line += i < p.observables.size() ? fmt::format(" {:>14.7g}", p.observables[i]) : fmt::format(" {:>14}", "");
  line += fmt::format(" {:>5} {:>9.2e} {:>10.3e} {:>9.2f}", p.iterations, p.residual, p.step, p.seconds);
  fmt::print("{}\n", line);
  std::fflush(stdout);
}

void ProgressPrinter::on_rejected(double lambda, double step, const Status& why) {
  fmt::print("         step rejected near {} = {:.8g} (step {:.3e}): {}; tried again shorter\n", parameter_, lambda,
             step, why.describe());
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
