// `keller export ORBITS.h5 --orbit ROW`: one orbit of an orbit branch (keller trace --orbit) as an
// animation for ParaView. Each row of an orbit branch stores the orbit's u0, period and parameter,
// which determine it; the export integrates it again over one period, on the grid of an adaptive
// run at the branch's [orbit] method and tolerances with the frame times added, and writes the
// fields at `frames` + 1 evenly spaced times from 0 to T into ORBITS-orbitROW.h5 with an XDMF
// temporal collection ORBITS-orbitROW.xdmf beside it (a problem without a mesh: its fields, such as
// profiles, without the XDMF file).
#pragma once

#include <string>

namespace keller {

// ROW: a row number or a located point's label (pd1, stop1, ...); frames 0: the branch scene's
// orbit.frames. Returns the exit code; throws
// std::invalid_argument for a file that is not an orbit branch or a row without a stored orbit.
int export_orbit(const std::string& input, const std::string& row, int frames);

// The files it writes for `input` and `row` (the row as given).
std::string orbit_export_path(const std::string& input, const std::string& row);

}  // namespace keller
