// keller's exit codes, the same for every command and every kind of error (docs/output.md, --help).
#pragma once

namespace keller::exit_code {

inline constexpr int ok = 0;
// A numerical failure: the first steady state did not converge (nothing written), a branch could
// not start (StopCode::StartFailed), or it ended at the step-size floor (its file holds every point
// before it).
inline constexpr int numerical_failure = 1;
// Bad command line, scene, study or path, or an output (or study folder) that another keller run
// is writing: stopped before any work, nothing written.
inline constexpr int usage = 2;
// A file could not be written or kept: a full disk, a file-size limit, an I/O error, or an output
// replaced by another file while the run wrote it. What was completed is kept (the message says
// where; a trace's or evolve's points in OUT.h5.part, which the same command continues).
inline constexpr int io_failure = 3;
// An error keller has no message of its own for: a defect of keller ("keller: internal error:
// ...", asking for a report). Files are left as the error found them (a trace's or evolve's
// points in OUT.h5.part, which the same command continues).
inline constexpr int internal_error = 4;
// Stopped by SIGINT or SIGTERM: everything completed is kept and the same command continues it.
inline constexpr int interrupted = 130;

// The table above, for --help.
inline constexpr const char* help =
    "Exit codes: 0 done; 1 numerical failure (the first steady state did not converge, the branch could not start, "
    "or it ended at the step-size floor); 2 bad command line, scene or path, or an output another keller run is "
    "writing (nothing written); 3 a file could not be written (full disk, file-size limit, I/O error, an output "
    "replaced during the run: what was completed is kept, and the message says where); 4 internal error (a defect "
    "of keller: please report it); 130 interrupted by SIGINT or SIGTERM "
    "(everything completed is kept; run the same command again to continue).";

}  // namespace keller::exit_code
