// What a run says of points it detected but could not locate, step by step: near a hard point the
// same detection fails at every step (a determinant whose sign is rounding), and saying it each
// time floods the terminal. The first of a run of the same note at successive steps is said, the
// rest counted and summed up in one line when that run ends (a step without it, or the end of the
// branch); runs of different notes are counted apart.
#pragma once

#include <map>
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
  struct Run {
    int repeats = 0, row = -1;
    long step = 0;  // the last step it was found at
  };
  static std::string summary(const std::string& key, const Run& run);
  std::map<std::string, Run> runs_;
  long step_ = 0;
};

}  // namespace keller
