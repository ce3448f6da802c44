// SIGINT and SIGTERM while a command writes results: the handler only records the signal and
// asks the running continuation, if any, to stop after its current point; the command polls
// requested() between the steps of its own work and stops cleanly, keeping what it completed.
#pragma once

namespace keller {

class Continuation;

class InterruptGuard {
 public:
  InterruptGuard();   // installs the handlers
  ~InterruptGuard();  // restores the previous ones
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

  static bool requested();
  // Asks for a stop as a signal does (a run hook that returns false: runs/RunHooks.hpp), while a
  // guard lives.
  static void request();
  // The continuation that a signal asks to stop (nullptr: none).
  static void forward_to(Continuation* run);
};

}  // namespace keller
