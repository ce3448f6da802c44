#include "runs/study/StudyTask.hpp"

#include <fmt/format.h>

#include <sys/resource.h>

#include <toml++/toml.h>
#include <filesystem>
#include <sstream>

#include "core/H5File.hpp"
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

void remove_output(const std::string& h5) {
  std::error_code ec;
  fs::remove(h5, ec);
  fs::remove(fs::path(h5).replace_extension(".xdmf"), ec);
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
  fs::create_directories(fs::path(study.task_output(task)).parent_path());
  const std::string out = study.task_output(task), work = PendingFile::temporary_for(out);
  // what another version of this task left is not this task's: it goes
  if (fs::exists(out) && !records_agree(stored_record(out), task.record, task.defaults)) remove_output(out);
  if (fs::exists(work) && !records_agree(stored_record(work), task.record, task.defaults)) fs::remove(work);
  TaskRecord record;
  record.hash = task.hash;
  try {
    if (study.kind() == "trace") {
      TraceArguments a;
      a.scene = task.scene;
      a.output = out;
      a.restart = task.start;
      a.overrides = task.overrides;
      run_trace(a, &record.summary);
    } else {
      SolveArguments a;
      a.scene = task.scene;
      a.output = out;
      a.overrides = task.overrides;
      run_solve(a, &record.summary);
    }
  } catch (const std::exception& e) {
    record.summary.exit_code = exit_code::usage;
    record.summary.reason = e.what();
  }
  struct rusage usage {};
  if (::getrusage(RUSAGE_SELF, &usage) == 0) record.peak_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;  // KiB
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
    o << fmt::format("process_seconds = {:.17g}\npeak_mb = {:.17g}\n", r.process_seconds, r.peak_mb);
    file.write(o.str());
  }
  file.commit();
}

bool task_current(const Study& study, const StudyTask& task, const TaskRecord& record) {
  if (record.hash == task.hash) return true;
  const std::string out = study.task_output(task);
  return fs::exists(out) && records_agree(stored_record(out), task.record, task.defaults);
}

bool task_done(const Study& study, const StudyTask& task) {
  const auto r = read_task_record(study, task);
  return r && r->status == "done" && task_current(study, task, *r) && fs::exists(study.task_output(task));
}

}  // namespace keller
