// Helpers shared by the tests of trace's start modes (tests/unit/runs: BranchStartsTest,
// CurveStartsTest, TraceStartTest): settings for a run in one parameter, and the terminal output
// of a call.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "runs/TraceStart.hpp"

namespace keller::test {

// The default options of a trace in `parameter`, with no state scale yet (a new run's own).
inline TraceSettings trace_settings_in(const std::string& parameter) {
  TraceSettings s;
  s.continuation.parameter = parameter;
  s.continuation.state_scale = 0.0;
  return s;
}

// Runs `f` with the standard output captured (released also where `f` throws); returns it.
template <class F>
std::string said(F&& f) {
  testing::internal::CaptureStdout();
  try {
    f();
  } catch (...) {
    testing::internal::GetCapturedStdout();
    throw;
  }
  return testing::internal::GetCapturedStdout();
}

}  // namespace keller::test
