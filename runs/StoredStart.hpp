// Starting a run from a point stored in another branch file (--restart, --switch): the point
// must be a state of this scene's problem. The file must have been made by the same problem
// with the same physics (the stored physics record, compared key by key), hold as many
// unknowns, and have been traced at the same values of every parameter that this run keeps
// fixed; a switch must start at a located branch point. `force` turns each refusal into a
// warning.
#pragma once

#include <string>
#include <vector>

#include "continuation/BranchPoint.hpp"
#include "core/Problem.hpp"
#include "runs/SceneLoader.hpp"

namespace keller {

struct StoredStart {
  std::string flag;       // "--restart" or "--switch": names the source in messages
  std::string file;
  int row = -1;           // -1: the last stored point
  bool switching = false;
  bool force = false;
};

// "FILE.h5:ROW" with ROW a number or "last". Throws std::invalid_argument.
StoredStart parse_stored_start(const std::string& flag, const std::string& spec);

// Reads the stored point and checks it against the scene and its problem (see above); throws
// std::invalid_argument naming the file, the row and what differs. Returns the point and, in
// `warnings`, what `force` let through.
BranchPoint read_stored_start(const StoredStart& start, const LoadedScene& scene, const Problem& problem,
                              const std::string& parameter, std::vector<std::string>& warnings);

}  // namespace keller
