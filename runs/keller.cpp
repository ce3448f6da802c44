// keller: continuation and bifurcation of steady flows. The command-line program (runs/CommandLine.hpp).
#include "core/BlasThreads.hpp"
#include "runs/CommandLine.hpp"

int main(int argc, char** argv) {
  // the program owns its process's BLAS: one thread for small matrices (core/BlasThreads.hpp)
  keller::set_blas_thread_policy(true);
  return keller::run_command_line(argc, argv);
}
