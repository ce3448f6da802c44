#include "core/SignalPoint.hpp"

#include <csignal>
#include <cstdlib>
#include <map>
#include <stdexcept>
#include <string>

namespace keller {

void signal_point(std::string_view phase) {
  const char* at = std::getenv("KELLER_SIGNAL_AT");
  if (!at) return;
  std::string want(at);
  long nth = 1;
  if (const auto colon = want.find(':'); colon != std::string::npos) {
    nth = std::strtol(want.c_str() + colon + 1, nullptr, 10);
    want.resize(colon);
  }
  if (want != phase) return;
  static std::map<std::string, long> reached;
  if (++reached[want] != nth) return;
  const char* which = std::getenv("KELLER_SIGNAL");
  const std::string sig = which ? which : "KILL";
  if (sig == "THROW") throw std::logic_error("KELLER_SIGNAL=THROW at " + want);
  std::raise(sig == "INT" ? SIGINT : sig == "TERM" ? SIGTERM : sig == "STOP" ? SIGSTOP : SIGKILL);
}

}  // namespace keller
