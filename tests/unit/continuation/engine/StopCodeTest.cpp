// Why a branch ended (continuation/engine/StopCode): the names, and which ends are failures (exit
// code 1: the step floor and a start that failed).
#include <gtest/gtest.h>

#include <string>

#include "continuation/engine/StopCode.hpp"

using namespace keller;

TEST(StopCode, NamesAndFailures) {
  const struct {
    StopCode code;
    std::string name;
    bool failure;
  } codes[] = {
      {StopCode::UpperBound, "upper-bound", false},
      {StopCode::LowerBound, "lower-bound", false},
      {StopCode::StopObservable, "stop-observable", false},
      {StopCode::MaxSteps, "max-steps", false},
      {StopCode::StepFloor, "step-floor", true},
      {StopCode::StartFailed, "start-failed", true},
      {StopCode::Interrupted, "interrupted", false},
  };
  for (const auto& c : codes) {
    EXPECT_EQ(to_string(c.code), c.name);
    EXPECT_EQ(is_failure(c.code), c.failure) << c.name;
  }
}
