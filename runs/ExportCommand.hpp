// `keller export BRANCH.h5 [--csv FILE|-] [--xdmf]`: the branch table (or the time table of a
// `keller evolve` run) as CSV (to a file or the standard output), and the fields of the stored
// solutions (states) with an XDMF file for ParaView.
#pragma once

#include <string>

namespace keller {

struct ExportArguments {
  std::string input;
  std::string csv;    // write the branch table as CSV here ("-": the standard output)
  bool xdmf = false;  // write fields of the stored solutions and an XDMF file
  std::string orbit;  // an orbit branch's row (or label): its orbit over a period as an animation (runs/OrbitExport)
  int frames = 0;     // of that animation (0: the branch's orbit.frames)
};
int run_export(const ExportArguments& args);

}  // namespace keller
