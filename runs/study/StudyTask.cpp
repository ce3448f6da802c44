#include "runs/study/StudyTask.hpp"

#include <fmt/format.h>

#include <sys/resource.h>
#include <unistd.h>

#include <toml++/toml.h>
#include <chrono>
#include <filesystem>
#include <sstream>

#include "continuation/output/BranchFile.hpp"
#include "core/H5File.hpp"
#include "core/IoError.hpp"
#include "core/OutputLock.hpp"
#include "core/PendingFile.hpp"
#include "runs/ExitCode.hpp"
#include "runs/OutputFile.hpp"
#include "runs/SolveCommand.hpp"
#include "runs/TraceCommand.hpp"

namespace keller {

namespace fs = std::filesystem;

namespace {

// The record of the run stored in an output file (/problem/run), or "" when there is none.
std::string stored_record(const std::string& path) {
  try {
    H5File f(path, H5File::Mode::Read);
    return f.exists("/problem/run") ? f.read_string("/problem/run") : "";
  } catch (const std::exception&) {
    return "";
  }
}

// Moves `path` to FOLDER/set_aside/STEM-N.EXT (the first N free) and says why.
void set_aside(const Study& study, const StudyTask& task, const std::string& path, const std::string& why) {
  const fs::path from(path), folder = fs::path(study.folder()) / "set_aside";
  std::error_code ec;
  fs::create_directories(folder, ec);
  fs::path to;
  for (int n = 1; to.empty() || fs::symlink_status(to, ec).type() != fs::file_type::not_found; ++n)
    to = folder / fmt::format("{}-{}{}", from.stem().string(), n, from.extension().string());
  fs::rename(from, to, ec);
  if (ec)
    throw IoError(fmt::format("task {} ({}): '{}' {}, and cannot be set aside as '{}': {}", task.index, task.label(),
                              path, why, to.string(), ec.message()));
  fmt::print("task {} ({}): '{}' {}; set aside as '{}', the task runs again\n", task.index, task.label(), path, why,
             to.string());
  std::fflush(stdout);
}

// The task is run by another process (a duplicate of it, as a batch system may requeue a task),
// which holds its output: its files are left to it, and so is its record where it has finished
// it; else the record says so, interrupted (the study's next run continues the task), with the
// cost of the runs before the holder's, which the holder adds its own to.
TaskRecord left_to_its_holder(const Study& study, const StudyTask& task, const std::optional<TaskRecord>& earlier,
                              const std::string& why) {
  fmt::print(stderr, "keller: task {} ({}) is left to the process that runs it: {}\n", task.index, task.label(), why);
  TaskRecord r = earlier ? *earlier : TaskRecord{};
  r.hash = task.hash;
  r.status = "interrupted";
  r.pid = ::getpid();
  r.summary.exit_code = exit_code::interrupted;
  r.summary.reason = "another process runs the task: " + why;
  if (!task_done(study, task)) write_task_record(study, task, r);
  return r;
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out += c;
  }
  return out + "\"";
}

}  // namespace

TaskRecord run_study_task(const Study& study, const StudyTask& task) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::optional<TaskRecord> earlier = interrupted_record(study, task);
  fs::create_directories(fs::path(study.task_output(task)).parent_path());
  const std::string out = study.task_output(task), work = PendingFile::temporary_for(out);
  TaskRecord record;
  record.hash = task.hash;
  record.pid = ::getpid();
  OutputLock lock;  // the task's output is this process's before anything is set aside, to its record
  try {
    lock = hold_task_output(study, task);
    set_aside_foreign_outputs(study, task, lock);
    if (study.kind() != "solve") {
      TraceArguments a;
      a.scene = task.scene;
      a.output = out;
      if (study.kind() == "orbit") {  // the orbit branch from the task's located Hopf point
        a.from = task.start;
        a.orbit = true;
      } else {
        a.restart = task.start;
      }
      a.overrides = task.overrides;
      a.output_locked = true;
      run_trace(a, &record.summary);
    } else {
      SolveArguments a;
      a.scene = task.scene;
      a.output = out;
      a.overrides = task.overrides;
      a.output_locked = true;
      run_solve(a, &record.summary);
    }
  } catch (const OutputLocked& e) {
    return left_to_its_holder(study, task, earlier, e.what());
  } catch (const std::exception& e) {
    fail_unexpected(record.summary, e);
  }
  struct rusage usage {};
  if (::getrusage(RUSAGE_SELF, &usage) == 0) record.peak_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;  // KiB
  // a continued run's cost is its output's: this run's and the interrupted ones' together (and
  // this process as it saw itself: its executor, where there is one, measures it from outside)
  add_earlier_runs(record.summary, earlier ? &earlier->summary : nullptr);
  record.process_seconds = (record.summary.runs > 1 && earlier ? earlier->process_seconds : 0.0) +
                           std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const int code = record.summary.exit_code;
  const bool written = !record.summary.output.empty() && record.summary.output == out && fs::exists(out);
  // a branch that ended at the step floor is a result, like one that reached its bound
  record.status = code == exit_code::interrupted ? "interrupted" : written ? "done" : "failed";
  if (record.status == "failed" && record.summary.reason.empty())
    record.summary.reason = fmt::format("the run ended with exit code {}", code);
  write_task_record(study, task, record);
  return record;
}

std::optional<TaskRecord> read_task_record(const Study& study, const StudyTask& task) {
  const std::string path = study.task_record(task);
  if (!fs::exists(path)) return std::nullopt;
  try {
    const toml::table t = toml::parse_file(path);
    TaskRecord r;
    r.hash = t["hash"].value_or(std::string());
    r.status = t["status"].value_or(std::string());
    r.attempts = static_cast<int>(t["attempts"].value_or(int64_t{1}));
    r.process_seconds = t["process_seconds"].value_or(0.0);
    r.peak_mb = t["peak_mb"].value_or(0.0);
    r.pid = static_cast<long>(t["pid"].value_or(int64_t{0}));
    RunSummary& s = r.summary;
    s.exit_code = static_cast<int>(t["exit_code"].value_or(int64_t{-1}));
    s.reason = t["reason"].value_or(std::string());
    s.output = t["output"].value_or(std::string());
    s.unknowns = static_cast<long>(t["unknowns"].value_or(int64_t{0}));
    s.points = static_cast<int>(t["points"].value_or(int64_t{0}));
    s.rejected = static_cast<int>(t["rejected"].value_or(int64_t{0}));
    s.factorisations = static_cast<long>(t["factorisations"].value_or(int64_t{0}));
    s.seconds = t["seconds"].value_or(0.0);
    s.lu_backend = t["lu_backend"].value_or(std::string());
    s.solves = static_cast<long>(t["solves"].value_or(int64_t{0}));
    s.nnz_lu = t["nnz_lu"].value_or(0.0);
    s.lu_peak_mb = t["lu_peak_mb"].value_or(0.0);
    s.factor_seconds = t["factor_seconds"].value_or(0.0);
    s.solve_seconds = t["solve_seconds"].value_or(0.0);
    s.runs = static_cast<int>(t["runs"].value_or(int64_t{1}));
    return r;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

void write_task_record(const Study& study, const StudyTask& task, const TaskRecord& r) {
  const std::string path = study.task_record(task);
  fs::create_directories(fs::path(path).parent_path());
  PendingFile file(path);
  {
    std::ostringstream o;
    const RunSummary& s = r.summary;
    o << fmt::format("# task {} of {}: {}\n", task.index, study.path(), task.label());
    o << fmt::format("hash = {}\nstatus = {}\nattempts = {}\nexit_code = {}\nreason = {}\noutput = {}\n",
                     quoted(r.hash), quoted(r.status), r.attempts, s.exit_code, quoted(s.reason), quoted(s.output));
    o << fmt::format("unknowns = {}\npoints = {}\nrejected = {}\nfactorisations = {}\nseconds = {:.17g}\n", s.unknowns,
                     s.points, s.rejected, s.factorisations, s.seconds);
    o << fmt::format("lu_backend = {}\n", quoted(s.lu_backend));
    o << fmt::format("solves = {}\nnnz_lu = {:.17g}\nlu_peak_mb = {:.17g}\n", s.solves, s.nnz_lu, s.lu_peak_mb);
    o << fmt::format("factor_seconds = {:.17g}\nsolve_seconds = {:.17g}\n", s.factor_seconds, s.solve_seconds);
    o << fmt::format("runs = {}\nprocess_seconds = {:.17g}\npeak_mb = {:.17g}\npid = {}\n", s.runs, r.process_seconds,
                     r.peak_mb, r.pid);
    file.write(o.str());
  }
  file.commit();
}

std::optional<TaskRecord> interrupted_record(const Study& study, const StudyTask& task) {
  auto r = read_task_record(study, task);
  if (r && r->status == "interrupted" && task_current(study, task, *r)) return r;
  return std::nullopt;
}

bool task_current(const Study& study, const StudyTask& task, const TaskRecord& record) {
  if (record.hash == task.hash) return true;
  const std::string out = study.task_output(task);
  return fs::exists(out) && study.record_agrees(task, stored_record(out));
}

bool task_done(const Study& study, const StudyTask& task) {
  const auto r = read_task_record(study, task);
  return r && r->status == "done" && task_current(study, task, *r) &&
         output_fault(study, task, study.task_output(task)).empty();
}

std::string output_fault(const Study& study, const StudyTask& task, const std::string& path) {
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(path, ec);
  if (st.type() == fs::file_type::not_found) return "is missing";
  if (st.type() == fs::file_type::symlink) return "is a symbolic link";
  if (st.type() == fs::file_type::directory) return "is a folder";
  if (st.type() != fs::file_type::regular) return "is not a regular file";
  std::string stored;
  try {
    H5File f(path, H5File::Mode::Read);
    if (!f.exists("/problem/run")) return "holds no record of its run (/problem/run)";
    stored = f.read_string("/problem/run");
    if (std::string difference; !study.record_agrees(task, stored, &difference))
      return "holds another run (it differs in: " + difference + ")";
    if (study.kind() == "solve" && !f.exists("/solution/u")) return "holds no solution (/solution/u)";
  } catch (const std::exception&) {
    return "cannot be read as an HDF5 file";
  }
  if (study.kind() != "solve") {
    try {
      const BranchTable t = read_branch_table(path);
      if (t.rows.rows() == 0) return "holds an empty branch";
      if (t.status == "running") return "holds a branch that was not finished";
    } catch (const std::exception& e) {
      return std::string("holds a branch that cannot be read: ") + e.what();
    }
  }
  return "";
}

OutputLock hold_task_output(const Study& study, const StudyTask& task) {
  const std::string out = study.task_output(task);
  return OutputLock(OutputLock::path_for(out), "'" + out + "'");
}

void set_aside_foreign_outputs(const Study& study, const StudyTask& task, const OutputLock& held) {
  const std::string out = study.task_output(task), work = PendingFile::temporary_for(out);
  if (held.path() != OutputLock::path_for(out))
    throw std::logic_error(
        fmt::format("task {}: its outputs are set aside under the lock of '{}' only", task.index, out));
  std::error_code ec;
  if (fs::symlink_status(out, ec).type() != fs::file_type::not_found)
    if (const std::string fault = output_fault(study, task, out); !fault.empty()) set_aside(study, task, out, fault);
  if (fs::symlink_status(work, ec).type() == fs::file_type::not_found) return;
  // an unfinished run is continued where its record agrees with the task's (the run checks the rest)
  const std::string stored = stored_record(work);
  if (stored.empty())
    set_aside(study, task, work, "is not an unfinished run that can be read");
  else if (std::string difference; !study.record_agrees(task, stored, &difference))
    set_aside(study, task, work, "holds the unfinished run of another (it differs in: " + difference + ")");
}

}  // namespace keller
