// `keller trace SCENE.toml -o OUT.h5 [--restart FILE.h5:ROW | --switch FILE.h5:ROW]`: traces a solution branch with
// the continuation engine and writes the branch file point by point (continuation/BranchFile).
#pragma once

#include <string>
#include <vector>

namespace keller {

struct TraceArguments {
  std::string scene;
  std::string output;                  // empty: <scene stem>.h5 here
  std::string restart;                 // "FILE.h5:ROW" (ROW may be "last"), or empty
  std::string switch_at;               // "FILE.h5:ROW": a new branch from the branch point stored there
  int switch_direction = +1;           // which side of the old branch (+1 or -1)
  std::vector<std::string> overrides;  // "section.key=value"
};

// Exit code: 0 the branch ended at a bound, stop observable or max_steps; 1 it ended at the
// step-size floor (numerical failure; the file holds every point before it) or the first
// steady state failed (no file); 2 bad input (no file); 130 interrupted (file complete).
int run_trace(const TraceArguments& args);
class SceneSchema;
// The keys `keller trace` reads beyond the problem's: [continuation] and [stability].
void declare_trace_keys(SceneSchema& schema);

struct ExportArguments {
  std::string input;
  std::string csv;    // write the branch table as CSV here
  bool xdmf = false;  // write fields of the stored solutions and an XDMF file
};
int run_export(const ExportArguments& args);

}  // namespace keller
