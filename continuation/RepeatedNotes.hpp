// What a run says of points it detected but could not locate, step by step: near a hard point the
// same detection fails at every step (a determinant whose sign is rounding), and saying it each
// time floods the terminal. The first of a run of the same note at successive steps is said, the
// rest counted and summed up in one line when the run ends (a step without it, another note, or
// the end of the branch).
#pragma once

#include <string>
#include <vector>

namespace keller {

class RepeatedNotes {
 public:
  struct Note {
    std::string key;   // what is the same from step to step (e.g. "branch-point 'det sign change'")
    std::string text;  // the whole note
  };
  // The notes of one step (`row`: the row after which they were found); returns what to say.
  std::vector<std::string> step(const std::vector<Note>& notes, int row);
  // The end of the branch: what is left to say.
  std::vector<std::string> finish();

 private:
  std::string summary() const;
  std::string key_;
  int repeats_ = 0, row_ = -1;
};

}  // namespace keller
