// A seam for the tests that interrupt a run in each of its phases. When the environment holds
// KELLER_SIGNAL_AT=<phase> or <phase>:<n>, the process sends itself KELLER_SIGNAL (INT, TERM,
// KILL or STOP; KILL when unset) the n-th time (default: the first) it reaches that phase. STOP
// holds the run there until SIGCONT, for tests that act on its files meanwhile. KELLER_SIGNAL=THROW
// throws std::logic_error there instead, standing for a defect of keller (an error no command has
// a message of its own for). Without the variable a call costs one getenv.
#pragma once

#include <string_view>

namespace keller {

void signal_point(std::string_view phase);

}  // namespace keller
