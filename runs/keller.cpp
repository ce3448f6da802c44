// keller: continuation and bifurcation of steady flows. The command-line program (runs/CommandLine.hpp).
#include "runs/CommandLine.hpp"

int main(int argc, char** argv) {
  keller::use_native_blas_kernels(argv);
  return keller::run_command_line(argc, argv);
}
