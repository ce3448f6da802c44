#include "continuation/RepeatedNotes.hpp"

#include <fmt/format.h>

namespace keller {

std::string RepeatedNotes::summary() const {
  return fmt::format("{} detected but not located again at {} successive step{}, the last after row {}", key_, repeats_,
                     repeats_ == 1 ? "" : "s", row_);
}

std::vector<std::string> RepeatedNotes::step(const std::vector<Note>& notes, int row) {
  std::vector<std::string> say;
  bool continued = false;
  for (const Note& n : notes) {
    if (!continued && !key_.empty() && n.key == key_) {
      ++repeats_;
      row_ = row;
      continued = true;
      continue;
    }
    if (repeats_ > 0) say.push_back(summary());
    say.push_back(n.text);
    key_ = n.key;
    repeats_ = 0;
    row_ = row;
    continued = true;
  }
  if (!continued) {
    if (repeats_ > 0) say.push_back(summary());
    key_.clear();
    repeats_ = 0;
  }
  return say;
}

std::vector<std::string> RepeatedNotes::finish() {
  std::vector<std::string> say;
  if (repeats_ > 0) say.push_back(summary());
  key_.clear();
  repeats_ = 0;
  return say;
}

}  // namespace keller
