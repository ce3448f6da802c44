// keller info FILE.h5: what a file keller wrote is (a branch, a two-parameter curve, a time
// series, a steady state, a study's collected table), the problem and scene it was made with (the
// keys that differ from their defaults), what made it (Provenance), and its stored rows with their
// kinds, parameter values and labels: what --restart, --switch and --from take.
#pragma once

#include <string>

namespace keller {

struct InfoArguments {
  std::string file;
  bool scene = false;  // print the whole resolved scene stored in the file instead
};

// Prints the description; returns an exit code (2 for a file that is not one of keller's).
int run_info(const InfoArguments& args);

}  // namespace keller
