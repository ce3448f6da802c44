// What every run's HDF5 file holds before its results: the resolved scene, the problem (name,
// summary, unknowns), the record of its physics (the keys that define the problem, and their
// hash) and the parameter values it started from. Restarts, branch switches and studies read
// them back to check that a stored state belongs to the scene at hand.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/H5File.hpp"
#include "core/HeldFile.hpp"
#include "core/Problem.hpp"
#include "core/RunFiles.hpp"
#include "runs/RunSummary.hpp"
#include "runs/SceneLoader.hpp"

namespace keller {

// The XDMF path beside an HDF5 path: OUT.h5 -> OUT.xdmf.
std::string xdmf_path_for(const std::string& h5_path);

// A 64-bit FNV-1a hash of a text, as 16 hexadecimal digits.
std::string text_hash(const std::string& text);

// Whether a record of "key = value" lines (Scene::canonical_values) stored in a file agrees with
// the present one: every key in both the same, none only in the file, and a key only in the present
// one (added to keller after the file was written) at its default (`defaults`: the lines of
// Scene::canonical_defaults), which keeps the physics the file was made with.
bool records_agree(const std::string& stored, const std::string& now, const std::string& defaults);
// What differs between them, e.g. 'fluid.model = "fene-p" in the file, "oldroyd-b" in this scene'
// (keys only in the present record at their defaults left out); empty when they agree.
std::string record_difference(const std::string& stored, const std::string& now, const std::string& defaults = "");

// The outputs of a run written to OUT.part and renamed to OUT when complete, with its fields added
// to OUT.fields.part first and XDMF files beside it (`with_fields`: declare_xdmf_outputs); `what`
// names OUT in messages ("branch file"). The temporary names (OUT.part, the OUT.part.part it is
// made as, OUT.fields.part and the lock OUT.lock) must not be links.
void declare_run_outputs(RunFiles& files, const std::string& out, const std::string& what, bool with_fields);
// The XDMF files of the HDF5 file `h5` (OUT.xdmf, and STEM_mode<k>.xdmf for a branch's critical
// eigenmodes), each written as NAME.pending by way of NAME.pending.part (PendingFile) and renamed
// once `h5` is in place: none of those names may be a link. The eigenmodes' count is known only
// once the branch has ended: the names of theirs that exist now are declared (a free name is no link).
void declare_xdmf_outputs(RunFiles& files, const std::string& h5);

// What an earlier run of a command left at `work` (OUT.part): nothing to take over (no file, an
// unreadable one, or one that `fresh` discards or that ended without being marked for publication:
// this run replaces it, saying why on the terminal), its unfinished run (status "running" while a
// writer ran, "interrupted ..." for a stopped one) to be continued, or its ended run, marked for
// publication (its exit code in `code_dataset`, -1 until then) and killed before it took its
// name, to be published.
struct LeftRun {
  enum class Kind { none, unfinished, ended };
  Kind kind = Kind::none;
  std::string status;  // the file's status
  int exit_code = 0;   // an ended run's exit code
  long rows = 0;       // the rows of its table
};
// `table` reads the rows and status of `work`, `code_dataset` is "/branch/exit_code" or
// "/evolve/exit_code", and `what` and `unit` name them ("branch", "rows"). The record of its run (/problem/run) must
// agree with `record` (records_agree, `defaults` the scene's) for it to be taken over: else an unfinished run throws
// std::invalid_argument (an unfinished run of another command is never overwritten) and an ended one is replaced.
using UnfinishedTable = std::function<std::pair<long, std::string>(const std::string& path)>;
LeftRun left_run(const std::string& work, const std::string& record, const std::string& defaults, bool fresh,
                 const std::string& what, const std::string& unit, const std::string& code_dataset,
                 const UnfinishedTable& table);
// How a run that writes its file point by point ended.
struct RunEnd {
  bool interrupted = false;  // by SIGINT or SIGTERM: its file stays, to be continued
  bool failed = false;       // at the step-size floor, or at its start: it does not replace an existing output
};
// Runs `run`, which writes the run's file `written` at `work` (OUT.h5.part) point by point and says
// how the run ended, then `finish` ends the file (BranchFile::finish), given the exit code of a
// run that takes its name `out` (takes_its_name) and nothing for one that does not; returns how
// the run ended. An IoError on the way ends the command with exit code 3 (a CommandFailure), its
// message saying what `work` keeps and what the same command does with it (`what` and `unit` name
// the content and its rows: "branch", "point").
RunEnd write_run_file(const std::string& work, const std::string& out, const HeldFile& written, const std::string& what,
                      const std::string& unit, const std::function<RunEnd()>& run,
                      const std::function<void(std::optional<int>)>& finish);

// Refuses (IoError) to go on with `work` where it is not the file `written` the run wrote, saying
// that `work` and `target` are left as they are and where the run's file is: moved elsewhere, or
// (without a name left) saved as WORK.<pid> from the descriptor held.
void expect_written(const std::string& work, const std::string& target, const HeldFile& written);
// Writes /scene (resolved TOML), /problem (attributes name, summary, unknowns, physics_hash),
// /problem/physics (LoadedScene::physics()), /problem/parameters (an attribute per parameter) and
// /provenance (Provenance::current()).
void write_run_header(H5File& file, const LoadedScene& scene, const Problem& problem);

// The header of a stored run, as write_run_header left it (physics empty for files written
// before the record existed).
struct RunHeader {
  std::string problem;
  long unknowns = 0;
  std::string physics, physics_hash;
  std::map<std::string, double> parameters;
  std::string scene;  // the resolved scene's TOML
};
RunHeader read_run_header(const H5File& file);

// Writes a solution's fields, parameter values and observables under `group`.
void write_solution(H5File& file, const std::string& group, Problem& problem, const Vector& u);

}  // namespace keller
