// How many threads the dense BLAS under the sparse LU runs (OpenBLAS's kernels inside UMFPACK's and
// MUMPS's frontal matrices). Below kThreadedBlasUnknowns unknowns the fronts are too small for a
// second thread to buy time, while it spins between calls (docs/performance.md, "BLAS threads":
// about the same wall time with one, a third less CPU time, half the wall time where another
// process holds the other core), so where the policy is on SparseLU asks the BLAS for one thread
// when it factorises such a matrix, and for the BLAS's own count otherwise: the count OpenBLAS
// reported at keller's first call (OPENBLAS_NUM_THREADS, GOTO_NUM_THREADS or OMP_NUM_THREADS, or
// the cores the process may use), so that a limit a user set stays a limit. A BLAS other than
// OpenBLAS is left as it is. With OpenBLAS's OpenMP build the call sets OpenMP's thread count too.
// The count is the process's: it must not change while another thread is inside the BLAS (keller
// factorises on one thread).
// The policy is a command-line program's: run_command_line (runs/CommandLine.hpp: the keller
// program, a program of one's own problems) turns it on unless the program has set it. Elsewhere it
// is off unless set: the Python package sets it off (numpy may share the process's OpenBLAS).
#pragma once

#include <string>

namespace keller {

inline constexpr long kThreadedBlasUnknowns = 20000;

// The policy, as a function: one thread below kThreadedBlasUnknowns unknowns, else `available`
// (the BLAS's own count), never fewer than one.
int blas_threads_for_unknowns(long unknowns, int available);

// Whether SparseLU applies the policy when it factorises a matrix: off until set.
void set_blas_thread_policy(bool on);
bool blas_thread_policy();
// Sets it where nothing has (run_command_line: on).
void default_blas_thread_policy(bool on);

// Sets the BLAS's threads for a matrix of `unknowns` unknowns by the policy (where the BLAS is
// OpenBLAS; else nothing). Returns the threads set, or 0 where the BLAS has no such control.
int use_blas_threads_for(long unknowns);

// The BLAS's present thread count (OpenBLAS), or 0 where it cannot be asked.
int blas_threads();

// OpenBLAS's kernels: it picks them for the CPU when it loads, and a CPU newer than its table
// gets its generic Prescott (SSE3) kernels: OpenBLAS 0.3.21 on an Intel Xeon of model 207 with
// AVX-512, where SkylakeX's made W3's factorisations 1.6 times and its cylinder branch 1.3 times
// faster (docs/performance.md, "BLAS kernels"). OPENBLAS_CORETYPE, read when OpenBLAS loads,
// chooses them (runs/CommandLine.hpp, use_native_blas_kernels).
// The kernels' name (openblas_get_corename), or "" where the BLAS is not OpenBLAS.
std::string blas_core();
// The policy, as a function: the kernels to ask for instead of `core` on a CPU with these
// features: where core is "Prescott" (case aside), "SkylakeX" with AVX-512 (F, BW, DQ and VL),
// else "Haswell" with AVX2 and FMA; else "" (keep them).
std::string better_blas_core(const std::string& core, bool avx2_and_fma, bool avx512);
// better_blas_core for this process's BLAS and CPU.
std::string better_blas_core();

}  // namespace keller
