// `keller trace SCENE.toml -o OUT.h5 [--restart FILE.h5:ROW]`: traces a solution branch with
// the continuation engine and writes the branch file point by point (continuation/BranchFile).
#pragma once

#include <string>
#include <vector>

namespace keller {

struct TraceArguments {
  std::string scene;
  std::string output;                  // empty: <scene stem>.h5 here
  std::string restart;                 // "FILE.h5:ROW" (ROW may be "last"), or empty
  std::vector<std::string> overrides;  // "section.key=value"
};

// Exit code: 0 the branch ended at a bound, stop observable or max_steps; 1 it ended at the
// step-size floor (numerical failure; the file holds every point before it) or the first
// steady state failed (no file); 2 bad input (no file); 130 interrupted (file complete).
int run_trace(const TraceArguments& args);

struct ExportArguments {
  std::string input;
  std::string csv;    // write the branch table as CSV here
  bool xdmf = false;  // write fields of the stored solutions and an XDMF file
};
int run_export(const ExportArguments& args);

}  // namespace keller
