#include "runs/ExportCommand.hpp"

#include <fmt/format.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <optional>

#include "continuation/output/BranchFile.hpp"
#include "continuation/output/TimeSeriesFile.hpp"
#include "core/H5File.hpp"
#include "core/IoError.hpp"
#include "core/OutputLock.hpp"
#include "core/PendingFile.hpp"
#include "core/RunFiles.hpp"
#include "runs/BranchOutput.hpp"
#include "runs/CommandRun.hpp"
#include "runs/EvolveCommand.hpp"
#include "runs/ExitCode.hpp"
#include "runs/Interrupts.hpp"
#include "runs/OrbitExport.hpp"
#include "runs/OutputFile.hpp"
#include "runs/SceneLoader.hpp"
#include "runs/TraceCommand.hpp"

namespace keller {

namespace fs = std::filesystem;

namespace {

// The table of a branch file or of a time-series file (keller evolve), as the file holds it.
struct Table {
  std::vector<std::string> columns;
  Eigen::MatrixXd rows;
  std::string status;
  bool time_series = false;
  std::string parameter;  // a branch's
};

Table read_table(const std::string& path) {
  bool series = false;
  {
    H5File f(path, H5File::Mode::Read);
    series = f.exists("/evolve/table");
  }
  Table t;
  t.time_series = series;
  if (series) {
    TimeTable s = read_time_table(path);
    t.columns = std::move(s.columns);
    t.rows = std::move(s.rows);
    t.status = std::move(s.status);
  } else {
    BranchTable b = read_branch_table(path);
    t.columns = std::move(b.columns);
    t.rows = std::move(b.rows);
    t.status = std::move(b.status);
    t.parameter = std::move(b.parameter);
  }
  return t;
}

// The table as CSV text: a branch's `kind` column by its names (point, start, stop, ...:
// to_string(PointKind)), every other value with all its digits.
std::string csv_text(const Table& t) {
  std::string o;
  long kind = -1;
  for (size_t j = 0; j < t.columns.size(); ++j) {
    o += (j ? "," : "") + t.columns[j];
    if (!t.time_series && t.columns[j] == "kind") kind = static_cast<long>(j);
  }
  o += "\n";
  for (long i = 0; i < t.rows.rows(); ++i) {
    for (long j = 0; j < t.rows.cols(); ++j) {
      o += j ? "," : "";
      const double v = t.rows(i, j);
      if (j == kind && v >= 0 && v <= static_cast<int>(PointKind::Hopf) && v == static_cast<int>(v))
        o += to_string(static_cast<PointKind>(static_cast<int>(v)));
      else
        o += fmt::format("{:.17g}", v);
    }
    o += "\n";
  }
  return o;
}

// Refuses fields for a file without a mesh (a 1D problem's): there are none for ParaView.
void expect_mesh(const std::string& path) {
  H5File f(path, H5File::Mode::Read);
  if (f.exists("/mesh")) return;
  const std::string problem =
      f.exists("/problem") && f.has_attribute("/problem", "name") ? f.read_string_attribute("/problem", "name") : "?";
  throw std::invalid_argument(
      fmt::format("'{}' has no mesh (problem '{}'): there are no fields to write for --xdmf (--csv writes its table)",
                  path, problem));
}

// Whether the branch file was closed by its writer (it can then be opened for writing; a file
// whose writer runs or was killed cannot).
bool closed_cleanly(const std::string& path) {
  try {
    H5File probe(path, H5File::Mode::ReadWrite);
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

// Companion of a branch file that cannot take its fields: BRANCH-fields.h5 beside it.
std::string companion_for(const std::string& branch) {
  const fs::path p(branch);
  return (p.parent_path() / (p.stem().string() + "-fields.h5")).string();
}

// The fields of the stored solutions (states) of the file at `input` (its table `t`), from the
// problem its stored scene builds: written into the file and an XDMF file beside it, or where its
// writer runs or was killed, into the companion BRANCH-fields.h5. Returns the exit code: 130 where a
// signal stopped it (nothing changed).
int export_fields(const std::string& input, const Table& t) {
  std::string scene_text;
  {
    H5File f(input, H5File::Mode::Read);
    scene_text = f.read_string("/scene");
  }
  LoadedScene loaded =
      load_scene_text(scene_text, input + ":/scene", t.time_series ? declare_evolve_keys : declare_trace_keys);
  auto problem = loaded.type->build(loaded.scene);
  if (t.time_series) {  // the parameters the run used (the scene's, or those of the point it started from)
    H5File f(input, H5File::Mode::Read);
    for (const auto& [name, value] : read_run_header(f).parameters)
      if (problem->parameters().has(name)) problem->parameters().set(name, value);
  }
  const int p = t.time_series ? -1 : problem->parameters().index(t.parameter);
  const FieldsAt fields_at = [&](const Vector& u, double lambda) {
    if (p >= 0) problem->parameters().set(p, lambda);
    return problem->fields(u);
  };
  const auto fields_of = [&](const Vector& u) { return problem->fields(u); };
  const std::string xdmf = xdmf_path_for(input);
  if (closed_cleanly(input)) {
    const PublishedBranch b = publish_output(input, input, xdmf, true,
                                             t.time_series ? series_fields(fields_of, &InterruptGuard::requested)
                                                           : branch_fields(xdmf, fields_at, &InterruptGuard::requested),
                                             &InterruptGuard::requested);
    if (!b.fields) {
      fmt::print("interrupted: {} is as it was\n", input);
      return exit_code::interrupted;
    }
    fmt::print("wrote the fields into {} and {}\n", input, xdmf);
    return exit_code::ok;
  }
  // a file whose writer runs or was killed takes no datasets: the fields go beside it
  const std::string companion = companion_for(input);
  PendingFile fields(companion);
  const std::string name = fs::path(companion).filename().string();
  const bool complete =
      t.time_series
          ? write_time_fields(input, fields.path(), xdmf + ".pending", name, fields_of, &InterruptGuard::requested)
          : write_branch_fields(input, fields.path(), xdmf + ".pending", name, fields_at, &InterruptGuard::requested);
  if (!complete) {
    fmt::print("interrupted: nothing written\n");
    return exit_code::interrupted;
  }
  fields.commit();
  if (fs::exists(xdmf + ".pending")) fs::rename(xdmf + ".pending", xdmf);
  fmt::print("wrote the fields to {} and {}\n", companion, xdmf);
  return exit_code::ok;
}

// --orbit ROW: one orbit as an animation, its files declared and checked before any work.
int export_orbit_run(const ExportArguments& args) {
  if (!args.csv.empty() || args.xdmf)
    throw CommandFailure::bad_input("--orbit writes one orbit's animation: it excludes --csv and --xdmf");
  const std::string out = orbit_export_path(args.input, args.orbit);
  checking([&] {
    RunFiles files;
    files.input("orbit branch file", args.input);
    files.output("orbit fields file", out);
    files.temporary("orbit fields file's temporary", PendingFile::temporary_for(out));
    files.output("orbit XDMF file", xdmf_path_for(out));
    files.temporary("orbit XDMF file's temporary", xdmf_path_for(out) + ".pending");
    files.check();
  });
  InterruptGuard interrupts;
  try {
    return export_orbit(args.input, args.orbit, args.frames);
  } catch (const std::invalid_argument& e) {
    throw CommandFailure::bad_input(e.what());
  } catch (const std::exception& e) {
    if (is_io_failure(e)) throw CommandFailure::io_failure(e.what());
    throw CommandFailure::numerical("the orbit's export", {StatusCode::NotConverged, e.what()});
  }
}

}  // namespace

int run_export(const ExportArguments& args) {
  return run_command(nullptr, [&](RunSummary&) {
    if (!args.orbit.empty()) return export_orbit_run(args);
    if (args.csv.empty() && !args.xdmf)
      throw CommandFailure::bad_input(
          "export needs --csv FILE (or - for the standard output) and/or --xdmf, or --orbit ROW");
    const bool to_stdout = args.csv == "-";
    OutputLock lock;  // --xdmf rewrites the file: one run at a time
    checking([&] {
      RunFiles files;
      files.input("branch or time-series file", args.input);
      if (!args.csv.empty() && !to_stdout) {
        files.output("--csv file", args.csv);
        files.temporary("--csv file's temporary", PendingFile::temporary_for(args.csv));
      }
      if (args.xdmf) {
        declare_xdmf_outputs(files, args.input);
        files.output("companion fields file", companion_for(args.input));
        files.temporary("companion fields file's temporary", PendingFile::temporary_for(companion_for(args.input)));
        files.temporary("copy with fields", args.input + ".fields.part");
        files.temporary("lock", OutputLock::path_for(args.input));
      }
      files.check();
      if (args.xdmf) {
        expect_mesh(args.input);
        lock = OutputLock(OutputLock::path_for(args.input), "'" + args.input + "'");
      }
    });
    InterruptGuard interrupts;
    try {
      const Table t = read_table(args.input);
      if (to_stdout) {
        write_all(STDOUT_FILENO, csv_text(t), "the standard output");
      } else if (!args.csv.empty()) {
        PendingFile csv(args.csv);
        csv.write(csv_text(t));
        csv.commit();
        fmt::print("wrote {} ({} rows; status: {})\n", args.csv, t.rows.rows(), t.status);
      }
      return args.xdmf ? export_fields(args.input, t) : exit_code::ok;
    } catch (const std::exception& e) {
      if (is_io_failure(e)) throw CommandFailure::io_failure(e.what());
      throw CommandFailure::bad_input(e.what());
    }
  });
}

}  // namespace keller
