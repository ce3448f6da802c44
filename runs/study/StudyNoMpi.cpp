// The MPI executor of a keller built without MPI (CMake found none): under mpirun it says so.
#include <fmt/format.h>

#include <cstdlib>

#include "runs/ExitCode.hpp"
#include "runs/study/StudyRunner.hpp"

namespace keller {

bool under_mpi() { return std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE"); }

int run_study_mpi(const Study&, int&, char**&) {
  fmt::print(stderr,
             "keller: error: this keller was built without MPI (install libopenmpi-dev and rebuild), so it "
             "cannot share a study between the ranks of mpirun; run it without mpirun, with --jobs N\n");
  return exit_code::usage;
}

}  // namespace keller
