// keller's exit codes, the same for every command and every kind of error (docs/output.md, --help).
#pragma once

namespace keller::exit_code {

inline constexpr int ok = 0;
// A numerical failure: the first steady state did not converge (nothing written), or a branch
// ended at the step-size floor (its file holds every point before it).
inline constexpr int numerical_failure = 1;
// Bad command line, scene, study or path: stopped before any work, nothing written.
inline constexpr int usage = 2;
// Stopped by SIGINT or SIGTERM: everything completed is kept and the same command continues it.
inline constexpr int interrupted = 130;

// The table above, for --help.
inline constexpr const char* help =
    "Exit codes: 0 done; 1 numerical failure (the first steady state did not converge, or the branch ended at the "
    "step-size floor); 2 bad command line, scene or path (nothing written); 130 interrupted by SIGINT or SIGTERM "
    "(everything completed is kept; run the same command again to continue).";

}  // namespace keller::exit_code
