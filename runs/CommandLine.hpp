// keller's command line as a library function: the `keller` program is
//   int main(int argc, char** argv) { return keller::run_command_line(argc, argv); }
// and a program of a user's own problems registers them first (problems/ProblemRegistry.hpp,
// register_problem_type) and then hands over the same way: it has every command (solve, trace,
// evolve, export, info, study, --help-scene) for keller's problem types and its own
// (docs/own_problem.md). Studies run their tasks in this same program (/proc/self/exe).
#pragma once

namespace keller {

// Parses argv, runs the command and returns its exit code (runs/ExitCode.hpp: 0 done, 1 numerical
// failure, 2 bad command line or input, 3 write failure, 4 internal error, 130 interrupted).
// Prints every error itself; throws nothing. Turns the BLAS thread policy on (one thread for
// matrices below 20,000 unknowns, core/BlasThreads.hpp) unless the program has set it.
int run_command_line(int argc, char** argv);

// Where OpenBLAS runs its generic Prescott kernels on a CPU with AVX2 or AVX-512 (a CPU newer than
// its table, core/BlasThreads.hpp) and OPENBLAS_CORETYPE is not set: sets it to the kernels the CPU
// has and runs the program again (execv of /proc/self/exe with the same argv; OpenBLAS reads the
// variable only when it loads). Call it first in main, before anything is printed or started
// (MPI_Init included); the keller program does. Returns where nothing is to change or the exec
// failed, or where the program was started through the dynamic loader (ld.so PROGRAM ...).
// KELLER_BLAS_KERNELS=keep turns it off (tools that run the program under their own control, as
// valgrind, want it off).
void use_native_blas_kernels(char** argv);

}  // namespace keller
