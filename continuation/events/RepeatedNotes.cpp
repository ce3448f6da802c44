#include "continuation/events/RepeatedNotes.hpp"

#include <fmt/format.h>

namespace keller {

std::string RepeatedNotes::summary(const std::string& key, const Run& run) {
  return fmt::format("{} detected but not located again at {} successive step{}, the last after row {}", key,
                     run.repeats, run.repeats == 1 ? "" : "s", run.row);
}

std::vector<std::string> RepeatedNotes::step(const std::vector<Note>& notes, int row) {
  ++step_;
  std::vector<std::string> say;
  for (const Note& n : notes) {
    auto it = runs_.find(n.key);
    if (it != runs_.end() && it->second.step >= step_ - 1) {
      if (it->second.step < step_) ++it->second.repeats;  // (the same note twice in one step: once)
      it->second.step = step_;
      it->second.row = row;
      continue;
    }
    say.push_back(n.text);
    runs_[n.key] = Run{0, row, step_};
  }
  // the runs this step did not continue have ended
  for (auto it = runs_.begin(); it != runs_.end();) {
    if (it->second.step == step_) {
      ++it;
      continue;
    }
    if (it->second.repeats > 0) say.push_back(summary(it->first, it->second));
    it = runs_.erase(it);
  }
  return say;
}

std::vector<std::string> RepeatedNotes::finish() {
  std::vector<std::string> say;
  for (const auto& [key, run] : runs_)
    if (run.repeats > 0) say.push_back(summary(key, run));
  runs_.clear();
  return say;
}

}  // namespace keller
