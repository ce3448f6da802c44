// Why a command stops early (runs/CommandFailure): each kind's exit code (runs/ExitCode.hpp), the
// line on stderr and the reason a study records, as the commands printed them before the one
// failure path existed.
#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>

#include "core/IoError.hpp"
#include "runs/CommandFailure.hpp"
#include "runs/ExitCode.hpp"

using namespace keller;

TEST(CommandFailure, BadInputAndIoFailuresAreErrorsWithTheirCodes) {
  const CommandFailure bad = CommandFailure::bad_input("--force applies to a start from --restart");
  EXPECT_EQ(bad.code(), exit_code::usage);
  EXPECT_EQ(bad.line(), "keller: error: --force applies to a start from --restart");
  EXPECT_EQ(bad.reason(), "--force applies to a start from --restart");
  const CommandFailure io = CommandFailure::io_failure("disk full; nothing written");
  EXPECT_EQ(io.code(), exit_code::io_failure);
  EXPECT_EQ(io.line(), "keller: error: disk full; nothing written");
  const CommandFailure own(exit_code::numerical_failure, "the eigenvector's real part is zero");
  EXPECT_EQ(own.code(), exit_code::numerical_failure);
  EXPECT_EQ(own.line(), "keller: error: the eigenvector's real part is zero");
}

TEST(CommandFailure, ANumericalFailureSaysWhatFailedAndThatNothingWasWritten) {
  const Status st{StatusCode::NotConverged, "no convergence in 20 iterations"};
  const CommandFailure f = CommandFailure::numerical("the first steady state failed", st);
  EXPECT_EQ(f.code(), exit_code::numerical_failure);
  EXPECT_EQ(f.line(), "keller: the first steady state failed: " + st.describe() + "; no output written");
  EXPECT_EQ(f.reason(), "the first steady state failed: " + st.describe());
}

// An error without a message of its own: a file that could not be written (IoError, an error of
// std::filesystem) is exit 3, anything else a defect of keller (exit 4) asking for a report; what
// was kept is said after the error.
TEST(CommandFailure, AnUnexpectedErrorIsAnIoFailureOrADefect) {
  const CommandFailure io = CommandFailure::unexpected(IoError("cannot write 'a.h5'"), "the branch stays in a.h5.part");
  EXPECT_EQ(io.code(), exit_code::io_failure);
  EXPECT_EQ(io.line(), "keller: error: cannot write 'a.h5'; the branch stays in a.h5.part");
  const CommandFailure fs = CommandFailure::unexpected(
      std::filesystem::filesystem_error("rename", std::make_error_code(std::errc::no_space_on_device)));
  EXPECT_EQ(fs.code(), exit_code::io_failure);
  const CommandFailure defect = CommandFailure::unexpected(std::logic_error("boom"));
  EXPECT_EQ(defect.code(), exit_code::internal_error);
  EXPECT_EQ(defect.line(),
            "keller: internal error: boom; this is a defect of keller: please report it, with the command and this "
            "message");
  EXPECT_EQ(defect.reason(),
            "internal error: boom; this is a defect of keller: please report it, with the command and this message");
}

TEST(CommandFailure, AReportPrintsItsLineAndFillsTheSummary) {
  RunSummary summary;
  testing::internal::CaptureStderr();
  const int code = CommandFailure::bad_input("'x.h5' is a directory").report(summary);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "keller: error: 'x.h5' is a directory\n");
  EXPECT_EQ(code, exit_code::usage);
  EXPECT_EQ(summary.exit_code, exit_code::usage);
  EXPECT_EQ(summary.reason, "'x.h5' is a directory");
}
