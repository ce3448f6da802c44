// Starting a run from a point stored in another branch file (--restart, --switch): the point
// must be a state of this scene's problem. The file must have been made by the same problem
// with the same physics (the stored physics record, compared key by key), hold as many
// unknowns, and the point's parameter values must be the scene's for every parameter that this
// run keeps fixed (the stored branch's own parameter included, when the run continues in
// another one, as AUTO and pde2path allow); a switch must start at a located branch point of a
// branch in the same parameter; a curve (--from) must start at a located point of its kind (a
// fold, a Hopf point, an event), and its branch's parameter is free. `force` turns each refusal into a warning.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "continuation/engine/BranchPoint.hpp"
#include "continuation/output/BranchFile.hpp"
#include "core/Problem.hpp"
#include "runs/OutputFile.hpp"
#include "runs/SceneLoader.hpp"

namespace keller {

struct StoredStart {
  std::string flag;  // "--restart" or "--switch": names the source in messages
  std::string file;
  int row = -1;       // -1: the last stored point
  std::string label;  // a located point's label instead of a row (PointLabels: fold1, hopf2, end)
  bool switching = false;
  bool curve = false;  // --from: a curve starts at the point, its branch's parameter an unknown of it
  // with --orbit: an orbit branch starts at the point, a located Hopf point (--from) or a period
  // doubling of an orbit branch (--switch, onto the doubled branch)
  bool orbit = false;
  // --from, and --switch with --orbit: the kind of located point the curve (or orbit branch) starts
  // at (Fold, Hopf, Event: an event or an end; PeriodDoubling)
  PointKind located = PointKind::Fold;
  bool force = false;
};

// "FILE.h5:ROW" with ROW a number, "last" or a located point's label (fold1, bp2, end). Throws
// std::invalid_argument.
StoredStart parse_stored_start(const std::string& flag, const std::string& spec);

struct StoredPoint {
  BranchPoint point;
  RunHeader header;   // of the file it came from
  BranchTable table;  // its branch
  // The value of `parameter` at the point: the point's own parameter value, or the value at
  // which its branch held `parameter` fixed (nothing if the file does not say).
  std::optional<double> value_of(const std::string& parameter) const;
};

// What keeps a stored file's state from being this scene's: another problem, or physics that differ
// (or are not recorded). Shared by every start from a stored file (a point, an evolve run).
std::vector<std::string> origin_refusals(const RunHeader& header, const LoadedScene& scene, const Problem& problem);
// Throws std::invalid_argument "WHERE: REFUSAL; pass --force ..." for the first refusal, or with
// `force` adds each to `warnings`; clears `refusals`.
void refuse_unless_forced(std::vector<std::string>& refusals, const std::string& where, bool force,
                          std::vector<std::string>& warnings);

// Reads the stored point (a label's row found in the file's table) and checks it against the scene and its problem for
// a run in `parameter` (see above); throws std::invalid_argument naming the file, the row and what differs. `warnings`
// receives what `force` let through.
StoredPoint read_stored_start(const StoredStart& start, const LoadedScene& scene, const Problem& problem,
                              const std::string& parameter, std::vector<std::string>& warnings);

}  // namespace keller
