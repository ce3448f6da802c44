#include "runs/Interrupts.hpp"

#include <atomic>
#include <csignal>

#include "continuation/Continuation.hpp"

namespace keller {

namespace {

volatile std::sig_atomic_t g_requested = 0;
std::atomic<Continuation*> g_run{nullptr};

extern "C" void on_signal(int) {
  g_requested = 1;
  if (Continuation* run = g_run.load()) run->request_stop();
}

struct sigaction g_old_int, g_old_term;

}  // namespace

InterruptGuard::InterruptGuard() {
  g_requested = 0;
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, &g_old_int);
  sigaction(SIGTERM, &sa, &g_old_term);
}

InterruptGuard::~InterruptGuard() {
  g_run.store(nullptr);
  sigaction(SIGINT, &g_old_int, nullptr);
  sigaction(SIGTERM, &g_old_term, nullptr);
}

bool InterruptGuard::requested() { return g_requested != 0; }

void InterruptGuard::request() { on_signal(0); }

void InterruptGuard::forward_to(Continuation* run) {
  g_run.store(run);
  if (run && g_requested) run->request_stop();
}

}  // namespace keller
