#include "runs/InfoCommand.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>

#include "continuation/output/BranchFile.hpp"
#include "continuation/output/TimeSeriesFile.hpp"
#include "core/H5File.hpp"
#include "runs/EvolveCommand.hpp"
#include "runs/ExitCode.hpp"
#include "runs/OutputFile.hpp"
#include "runs/PointLabels.hpp"
#include "runs/Provenance.hpp"
#include "runs/SceneLoader.hpp"
#include "runs/TraceCommand.hpp"

namespace keller {

namespace {

enum class FileKind { Branch, TimeSeries, Solution, Study };

// A number for people: 10 significant digits, no trailing noise.
std::string number(double v) { return fmt::format("{:.10g}", v); }

std::string attribute_or(const H5File& f, const std::string& object, const std::string& name) {
  return f.exists(object) && f.has_attribute(object, name) ? f.read_string_attribute(object, name) : std::string();
}

// The problem, its parameters, what made the file and its scene's keys that differ from their
// defaults (the stored scene loaded with the command's keys; where it no longer loads, the keys it
// did not mark as defaults).
void print_run(const H5File& f, const std::string& path, const std::function<void(SceneSchema&)>& keys) {
  const RunHeader h = read_run_header(f);
  if (!h.problem.empty())
    fmt::print("problem: {} ({} unknowns): {}\n", h.problem, h.unknowns, attribute_or(f, "/problem", "summary"));
  if (!h.parameters.empty()) {
    std::string line;
    for (const auto& [name, value] : h.parameters)
      line += fmt::format("{}{} = {}", line.empty() ? "" : ", ", name, number(value));
    fmt::print("parameters at the start: {}\n", line);
  }
  if (const auto p = Provenance::read(f))
    fmt::print("made by: keller {} (commit {}, {} build, linear solver {})\ncommand: {}\n", p->version, p->commit,
               p->build_type, p->linear_solver, p->command_line);
  else
    fmt::print("made by: a keller that did not record its version (no /provenance)\n");
  if (h.scene.empty()) return;
  const std::string source = attribute_or(f, "/scene", "source");
  try {
    const LoadedScene loaded = load_scene_text(h.scene, source.empty() ? path + ":/scene" : source, keys);
    fmt::print("\n{}# every key, with its default: keller info {} --scene\n", loaded.scene.non_default_toml(), path);
  } catch (const std::exception&) {
    std::string given;
    size_t start = 0;
    while (start < h.scene.size()) {
      const size_t end = std::min(h.scene.find('\n', start), h.scene.size());
      const std::string line = h.scene.substr(start, end - start);
      if (line.find("# default") == std::string::npos) given += line + "\n";
      start = end + 1;
    }
    fmt::print("\n# the scene as stored (it does not load in this keller), the keys its file set:\n{}", given);
  }
}

void print_branch(const H5File& f, const std::string& path) {
  const BranchTable t = read_branch_table(path);
  const RunHeader h = read_run_header(f);
  // a curve's other parameter is its observable named after a parameter (CurveProblem)
  std::string other;
  for (const std::string& o : t.observables)
    if (h.parameters.count(o) && o != t.parameter) other = o;
  const std::string curve = attribute_or(f, "/problem", "curve");
  if (!curve.empty())
    fmt::print("{}: {} {} curve in ({}, {}) (keller trace --curve), from {}\n", path, curve == "event" ? "an" : "a",
               curve, t.parameter, other, attribute_or(f, "/problem", "curve_from"));
  else
    fmt::print("{}: a branch in {} (keller trace)\n", path, t.parameter);
  for (const char* from : {"restarted_from", "switched_at"}) {
    const std::string v = attribute_or(f, "/problem", from);
    if (!v.empty()) fmt::print("{}: {}\n", from[0] == 'r' ? "restarted from" : "switched branches at", v);
  }
  fmt::print("{} rows, {} stored solutions; status: {}\n", t.rows.rows(), t.saved_rows.size(), t.status);
  print_run(f, path, declare_trace_keys);

  const std::vector<PointLabel> labels = point_labels(t);
  std::map<int, std::string> label_of;
  for (const PointLabel& l : labels) label_of[l.row] = l.label;
  std::vector<std::string> shown;
  if (!other.empty()) shown.push_back(other);
  for (const std::string& o : t.observables)
    if (shown.size() < 4 && o != other) shown.push_back(o);
  fmt::print("\nstored rows ({} FILE:ROW or FILE:LABEL takes these; labels name the located points):\n",
             curve.empty() ? "--restart, --switch, --from" : "--restart");
  std::string head = fmt::format("  {:>5}  {:<8} {:<6} {:>16}", "row", "label", "kind", t.parameter);
  for (const std::string& o : shown) head += fmt::format(" {:>16}", o);
  fmt::print("{}\n", head);
  const int kind = t.column("kind"), param = t.column(t.parameter), row_col = t.column("row");
  for (int r : t.saved_rows) {
    long i = -1;
    for (long k = 0; k < t.rows.rows(); ++k)
      if (static_cast<int>(t.rows(k, row_col)) == r) i = k;
    if (i < 0) continue;  // a killed run's solution whose table row was never written
    const auto it = label_of.find(r);
    std::string line =
        fmt::format("  {:>5}  {:<8} {:<6} {:>16}", r, it == label_of.end() ? "" : it->second,
                    to_string(static_cast<PointKind>(static_cast<int>(t.rows(i, kind)))), number(t.rows(i, param)));
    for (const std::string& o : shown) line += fmt::format(" {:>16}", number(t.rows(i, t.column(o))));
    fmt::print("{}\n", line);
  }
  fmt::print("located points: {}\n", describe_labels(labels));
}

void print_time_series(const H5File& f, const std::string& path) {
  const TimeTable t = read_time_table(path);
  fmt::print("{}: a time series (keller evolve)\n", path);
  const std::string from = attribute_or(f, "/problem", "restarted_from");
  if (!from.empty()) fmt::print("started from: {}\n", from);
  const int tc = t.column("t"), sc = t.column("step");
  if (t.rows.rows() > 0)
    fmt::print("{} steps, t = {} to {}; status: {}\n", static_cast<long>(t.rows(t.rows.rows() - 1, sc)),
               number(t.rows(0, tc)), number(t.rows(t.rows.rows() - 1, tc)), t.status);
  else
    fmt::print("no steps; status: {}\n", t.status);
  print_run(f, path, declare_evolve_keys);
  long rows = 0, cols = 0;
  const std::vector<double> saved =
      f.exists("/evolve/saved") ? f.read_matrix("/evolve/saved", &rows, &cols) : std::vector<double>{};
  fmt::print("\nstored states ({}):\n  {:>7} {:>16}\n", rows, "step", "t");
  constexpr long shown = 40;
  for (long i = 0; i < rows && cols >= 2; ++i) {
    if (rows > shown && i == shown / 2) {
      fmt::print("  ... {} more\n", rows - shown);
      i = rows - shown / 2;
    }
    fmt::print("  {:>7} {:>16}\n", static_cast<long>(saved[static_cast<size_t>(i * cols)]),
               number(saved[static_cast<size_t>(i * cols + 1)]));
  }
}

void print_solution(const H5File& f, const std::string& path) {
  fmt::print("{}: a steady state (keller solve)\n", path);
  if (f.exists("/solution/newton") && f.has_attribute("/solution/newton", "final_residual_norm"))
    fmt::print("final |F| = {:.3e}\n", f.read_double_attribute("/solution/newton", "final_residual_norm"));
  print_run(f, path, declare_trace_keys);
  if (f.exists("/solution/observables")) {
    fmt::print("\nobservables:\n");
    for (const std::string& name : f.attribute_names("/solution/observables"))
      fmt::print("  {} = {}\n", name, number(f.read_double_attribute("/solution/observables", name)));
  }
}

void print_study(const H5File& f, const std::string& path) {
  fmt::print("{}: a study's collected table (keller study)\n", path);
  const std::vector<std::string> status =
      f.exists("/study/status") ? f.read_strings("/study/status") : std::vector<std::string>{};
  std::map<std::string, int> count;
  for (const std::string& s : status) ++count[s];
  std::string counts;
  for (const auto& [s, n] : count) counts += fmt::format("{}{} {}", counts.empty() ? "" : ", ", n, s);
  fmt::print("{} tasks{}\n", status.size(), counts.empty() ? "" : ": " + counts);
  fmt::print("columns: {}\n", attribute_or(f, "/study", "columns"));
  if (const auto p = Provenance::read(f))
    fmt::print("made by: keller {} (commit {}, {} build, linear solver {})\ncommand: {}\n", p->version, p->commit,
               p->build_type, p->linear_solver, p->command_line);
}

}  // namespace

int run_info(const InfoArguments& args) {
  namespace fs = std::filesystem;
  if (!fs::is_regular_file(args.file)) {
    fmt::print(stderr, "keller: error: '{}' {}\n", args.file,
               fs::exists(args.file) ? "is not a file" : "does not exist");
    return exit_code::usage;
  }
  try {
    H5File f(args.file, H5File::Mode::Read);
    std::optional<FileKind> kind;
    if (f.exists("/branch/table"))
      kind = FileKind::Branch;
    else if (f.exists("/evolve/table"))
      kind = FileKind::TimeSeries;
    else if (f.exists("/solution"))
      kind = FileKind::Solution;
    else if (f.exists("/study"))
      kind = FileKind::Study;
    if (!kind) {
      fmt::print(stderr,
                 "keller: error: '{}' is an HDF5 file but not one keller wrote (no /branch, /evolve, /solution or "
                 "/study)\n",
                 args.file);
      return exit_code::usage;
    }
    if (args.scene) {
      if (!f.exists("/scene")) {
        fmt::print(stderr, "keller: error: '{}' holds no scene (a study's table has none: its tasks' files do)\n",
                   args.file);
        return exit_code::usage;
      }
      fmt::print("{}", f.read_string("/scene"));
      return exit_code::ok;
    }
    switch (*kind) {
      case FileKind::Branch: print_branch(f, args.file); break;
      case FileKind::TimeSeries: print_time_series(f, args.file); break;
      case FileKind::Solution: print_solution(f, args.file); break;
      case FileKind::Study: print_study(f, args.file); break;
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "keller: error: {}: {}\n", args.file, e.what());
    return exit_code::usage;
  }
  return exit_code::ok;
}

}  // namespace keller
