// Helpers shared by the study tests (tests/regression/StudyTest.cpp, StudyDamageTest.cpp).
#pragma once

#include <string>

namespace keller::test {

// Writes DIR/bratu.toml: 12 short Bratu branches, 4 grids x 3 ends (continuation.stop_above takes
// `ends`), the fold and u(1/2) at the stops collected; returns its path. The renewal cost is
// pinned: by default the chord's renewals follow the run's measured times, so two runs under
// different loads may differ in their factorisations and in the last digits (below the
// corrector's tolerance); pinned, every run of a task is the same to the bit, which is what the
// tests compare across executors and restarts.
std::string bratu_study(const std::string& dir, const std::string& ends = "2.0, 3.0, 4.0");
// A study's collected CSV without the columns that measure time and memory (the rest is
// deterministic).
std::string table_without_time(const std::string& csv);
// How often `what` occurs in `text`.
int count(const std::string& text, const std::string& what);

}  // namespace keller::test
