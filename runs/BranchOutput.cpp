#include "runs/BranchOutput.hpp"

#include <fmt/format.h>
#include <stdio.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "continuation/output/BranchFile.hpp"
#include "continuation/output/TimeSeriesFile.hpp"
#include "core/IoError.hpp"
#include "core/PendingFile.hpp"
#include "core/RunFiles.hpp"
#include "core/SignalPoint.hpp"
#include "runs/CommandFailure.hpp"
#include "runs/ExitCode.hpp"
#include "runs/Interrupts.hpp"
#include "runs/OutputFile.hpp"

namespace keller {

namespace fs = std::filesystem;

namespace {

// XDMF files are written as NAME.pending and take their names once the HDF5 file they refer to
// is in place.
constexpr const char* pending_suffix = ".pending";

void move_file(const std::string& from, const std::string& to) {
  if (std::rename(from.c_str(), to.c_str()) != 0)
    throw IoError(fmt::format("cannot rename '{}' to '{}': {}", from, to, std::strerror(errno)));
}

// Files removed when the scope ends unless released.
struct Scratch {
  std::vector<std::string> paths;
  bool released = false;
  Scratch() = default;
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;
  ~Scratch() {
    std::error_code ec;
    if (!released)
      for (const std::string& p : paths) fs::remove(p, ec);
  }
};

}  // namespace

PublishedBranch publish_output(const std::string& work, const std::string& target, const std::string& xdmf,
                               bool with_fields, const AddFields& add, const std::function<bool()>& stop,
                               const HeldFile* written) {
  PublishedBranch out;
  const bool in_place = same_file(work, target);
  HeldFile opened;
  if (!written || !written->held()) opened = HeldFile::open(work);
  const HeldFile& source = written && written->held() ? *written : opened;
  expect_written(work, target, source);
  if (with_fields) {
    const std::string h5_name = fs::path(target).filename().string();
    const std::string staged = target + ".fields.part";
    Scratch scratch;
    clear_leftover(staged);
    clear_leftover(xdmf + pending_suffix);
    scratch.paths = {staged, xdmf + pending_suffix};
    const HeldFile copy = source.copy_to(staged);
    const std::optional<std::vector<std::string>> more = add(staged, xdmf + pending_suffix, h5_name, pending_suffix);
    if (more) scratch.paths.insert(scratch.paths.end(), more->begin(), more->end());
    const bool complete = more && !(stop && stop());
    signal_point("fields-written");
    if (complete) {
      expect_written(staged, target, copy);
      sync_file(staged);
      move_file(staged, target);
      scratch.released = true;
      signal_point("published");
      for (const std::string& p : scratch.paths)
        if (p != staged && fs::exists(p)) move_file(p, p.substr(0, p.size() - std::string(pending_suffix).size()));
      out.fields = true;
      out.modes = static_cast<int>(more->size());
      std::error_code ec;
      if (!in_place && source.at(work)) fs::remove(work, ec);
      return out;
    }
  }
  if (!in_place) {
    sync_file(work);
    expect_written(work, target, source);
    move_file(work, target);
    signal_point("published");
  }
  return out;
}

AddFields branch_fields(const std::string& xdmf, const FieldsAt& fields, const std::function<bool()>& stop) {
  const std::string stem = fs::path(xdmf).replace_extension().string();
  return [stem, fields, stop](const std::string& staged, const std::string& xdmf_pending, const std::string& h5_name,
                              const std::string& suffix) -> std::optional<std::vector<std::string>> {
    if (!write_branch_fields(staged, staged, xdmf_pending, h5_name, fields, stop)) return std::nullopt;
    return write_branch_modes(staged, h5_name, stem, suffix, fields, stop);
  };
}

AddFields series_fields(const std::function<SolutionFields(const Vector& u)>& fields,
                        const std::function<bool()>& stop) {
  return [fields, stop](const std::string& staged, const std::string& xdmf_pending, const std::string& h5_name,
                        const std::string&) -> std::optional<std::vector<std::string>> {
    if (!write_time_fields(staged, staged, xdmf_pending, h5_name, fields, stop)) return std::nullopt;
    return std::vector<std::string>{};
  };
}

int publish_run(const std::string& work, const std::string& out, bool with_fields, const AddFields& add,
                const HeldFile& written, int code, const std::string& what, RunSummary& summary) {
  const std::string xdmf = xdmf_path_for(out);
  PublishedBranch published;
  try {
    published = publish_output(work, out, xdmf, with_fields, add, &InterruptGuard::requested, &written);
  } catch (const std::exception& e) {
    throw CommandFailure::unexpected(
        e, written.at(work) ? fmt::format("the {} stays in {} (the same command publishes it)", what, work) : "");
  }
  if (published.modes > 0)
    fmt::print("wrote {} critical eigenmode(s): {}_mode<k>.xdmf\n", published.modes,
               fs::path(xdmf).replace_extension().string());
  fmt::print("wrote {}\n", out);
  summary.output = out;
  summary.exit_code = code;
  if (with_fields && !published.fields) {
    fmt::print(
        "interrupted while writing the fields: the {} is complete in {} without them; `keller export {} --xdmf` "
        "writes them\n",
        what, out, out);
    summary.exit_code = exit_code::interrupted;
  }
  return summary.exit_code;
}

int publish_left_run(const std::string& work, const std::string& out, bool with_fields, const AddFields& add,
                     const LeftRun& left, const std::string& what, RunSummary& summary) {
  fmt::print("note: '{}' holds this command's {}, which ended before it was published; publishing it ({})\n", work,
             what, left.status);
  summary.reason = left.status;
  // nothing computed: its one row is the output's last, where it continued the earlier runs
  // (whose cost a study adds: add_earlier_runs), so that the output's rows are counted once
  summary.points = 1;
  summary.continued_from = static_cast<int>(left.rows) - 1;
  InterruptGuard interrupts;
  HeldFile written;
  try {
    written = HeldFile::open(work);
  } catch (const std::exception& e) {
    throw CommandFailure::unexpected(e);
  }
  return publish_run(work, out, with_fields, add, written, left.exit_code, what, summary);
}

}  // namespace keller
