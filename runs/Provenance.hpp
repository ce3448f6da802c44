// What made an output file: keller's version, the git commit it was built from, the build type,
// the sparse LU a scene gets by default in this build, and the command line of the run. `keller
// --version` prints it; every output file keeps it as attributes of /provenance.
#pragma once

#include <optional>
#include <string>

#include "core/H5File.hpp"

namespace keller {

struct Provenance {
  std::string version;        // CMake's project(VERSION)
  std::string commit;         // the git commit the build was configured at; "unknown" outside git
  std::string build_type;     // CMAKE_BUILD_TYPE
  std::string linear_solver;  // what linear_solver.backend = "auto" takes: "mumps" or "umfpack"
  std::string command_line;   // the run's arguments, quoted for a shell where needed; "unknown" if not recorded

  // This keller, with the command line record_command_line kept.
  static Provenance current();
  // Keeps the process's command line for current() (keller's main calls it first).
  static void record_command_line(int argc, char** argv);
  // The lines `keller --version` prints.
  std::string version_text() const;
  // Writes the attributes of /provenance (creating the group).
  void write(H5File& file) const;
  // /provenance of a file; nothing for a file written before keller kept it.
  static std::optional<Provenance> read(const H5File& file);
};

}  // namespace keller
