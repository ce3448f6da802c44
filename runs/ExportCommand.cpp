#include "runs/ExportCommand.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "continuation/BranchFile.hpp"
#include "core/H5File.hpp"
#include "core/PendingFile.hpp"
#include "core/RunFiles.hpp"
#include "runs/BranchOutput.hpp"
#include "runs/ExitCode.hpp"
#include "runs/Interrupts.hpp"
#include "runs/OutputFile.hpp"
#include "runs/SceneLoader.hpp"
#include "runs/TraceCommand.hpp"

namespace keller {

namespace fs = std::filesystem;

namespace {

void write_csv(std::ostream& o, const BranchTable& t) {
  for (size_t j = 0; j < t.columns.size(); ++j) o << (j ? "," : "") << t.columns[j];
  o << "\n";
  for (long i = 0; i < t.rows.rows(); ++i) {
    for (long j = 0; j < t.rows.cols(); ++j) o << (j ? "," : "") << fmt::format("{:.17g}", t.rows(i, j));
    o << "\n";
  }
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

}  // namespace

int run_export(const ExportArguments& args) {
  if (args.csv.empty() && !args.xdmf) {
    fmt::print(stderr, "keller: error: export needs --csv FILE (or - for the standard output) and/or --xdmf\n");
    return exit_code::usage;
  }
  const bool to_stdout = args.csv == "-";
  try {
    RunFiles files;
    files.input("branch file", args.input);
    if (!args.csv.empty() && !to_stdout) {
      files.output("--csv file", args.csv);
      files.output("--csv file's temporary", PendingFile::temporary_for(args.csv));
    }
    if (args.xdmf) {
      files.output("XDMF file", xdmf_path_for(args.input));
      files.output("companion fields file", companion_for(args.input));
    }
    files.check();
  } catch (const std::exception& e) {
    fmt::print(stderr, "keller: error: {}\n", e.what());
    return exit_code::usage;
  }
  InterruptGuard interrupts;
  try {
    const BranchTable t = read_branch_table(args.input);
    if (to_stdout) {
      write_csv(std::cout, t);
      std::cout.flush();
    } else if (!args.csv.empty()) {
      PendingFile csv(args.csv);
      {
        std::ofstream o(csv.path());
        write_csv(o, t);
        if (!o) throw std::runtime_error("cannot write '" + csv.path() + "'");
      }
      csv.commit();
      fmt::print("wrote {} ({} rows; status: {})\n", args.csv, t.rows.rows(), t.status);
    }
    if (args.xdmf) {
      // the problem, rebuilt from the scene stored in the file
      std::string scene_text;
      {
        H5File f(args.input, H5File::Mode::Read);
        scene_text = f.read_string("/scene");
      }
      LoadedScene loaded = load_scene_text(scene_text, args.input + ":/scene", declare_trace_keys);
      auto problem = loaded.type->build(loaded.scene);
      const int p = problem->parameters().index(t.parameter);
      const FieldsAt fields_at = [&](const Vector& u, double lambda) {
        problem->parameters().set(p, lambda);
        return problem->fields(u);
      };
      const std::string xdmf = xdmf_path_for(args.input);
      if (closed_cleanly(args.input)) {
        const PublishedBranch b =
            publish_branch(args.input, args.input, xdmf, true, fields_at, &InterruptGuard::requested);
        if (!b.fields) {
          fmt::print("interrupted: {} is as it was\n", args.input);
          return exit_code::interrupted;
        }
        fmt::print("wrote the fields into {} and {}\n", args.input, xdmf);
      } else {
        // a file whose writer runs or was killed takes no datasets: the fields go beside it
        const std::string companion = companion_for(args.input);
        PendingFile fields(companion);
        if (!write_branch_fields(args.input, fields.path(), xdmf + ".pending", fs::path(companion).filename().string(),
                                 fields_at, &InterruptGuard::requested)) {
          fmt::print("interrupted: nothing written\n");
          return exit_code::interrupted;
        }
        fields.commit();
        if (fs::exists(xdmf + ".pending")) fs::rename(xdmf + ".pending", xdmf);
        fmt::print("wrote the fields to {} and {}\n", companion, xdmf);
      }
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "keller: error: {}\n", e.what());
    return exit_code::usage;
  }
  return exit_code::ok;
}

}  // namespace keller
