// The last phase of a trace or of evolve, and `keller export --xdmf`: a finished branch (or time
// series) file gets the fields of its stored solutions and its critical eigenmodes, with XDMF files
// beside it for ParaView, without a moment at which a file on disk is damaged. The fields are added to a copy
// (TARGET.fields.part) that is renamed over the target; the XDMF files follow once it is there.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/HeldFile.hpp"
#include "core/SolutionFields.hpp"
#include "core/Types.hpp"
#include "runs/OutputFile.hpp"
#include "runs/RunSummary.hpp"

namespace keller {

using FieldsAt = std::function<SolutionFields(const Vector& u, double lambda)>;

struct PublishedBranch {
  bool fields = false;  // false: `stop` interrupted the fields (the branch is at the target without them)
  int modes = 0;        // eigenmode XDMF files written
};

// Writes the fields into the staged copy of a finished run's file (`staged`, opened for writing),
// the XDMF file at `xdmf_pending` (which names the HDF5 file `h5_name`, its final name) and any
// further files under names ending in `pending_suffix`; returns those further files, or nothing
// where it was stopped.
using AddFields = std::function<std::optional<std::vector<std::string>>(
    const std::string& staged, const std::string& xdmf_pending, const std::string& h5_name,
    const std::string& pending_suffix)>;

// Puts the closed file `work` at `target` (they may be the same file); when `with_fields`, the
// fields are first added (`add`) to a copy that is renamed over the target, and the XDMF files take
// their names once it is there. `work` is removed once the target holds it (unless it is the
// target). `written` (when given) is the file the run wrote: where `work` no longer names it, the
// target is left as it was, and so is the file at `work`, and the run's file, if it has no name
// left, is saved as WORK.<pid>; the IoError says so. Throws IoError (std::runtime_error for a file
// that cannot be read) on I/O errors, leaving `work` as it was.
PublishedBranch publish_output(const std::string& work, const std::string& target, const std::string& xdmf,
                               bool with_fields, const AddFields& add, const std::function<bool()>& stop,
                               const HeldFile* written = nullptr);

// What publish_output adds to a branch file: the fields of its stored solutions (`fields` at their
// parameter values), the XDMF file `xdmf` and one per critical eigenmode (STEM_mode<k>.xdmf);
// `stop` is asked between stored solutions.
AddFields branch_fields(const std::string& xdmf, const FieldsAt& fields, const std::function<bool()>& stop);
// What publish_output adds to a time-series file: the fields of its stored states and the XDMF file.
AddFields series_fields(const std::function<SolutionFields(const Vector& u)>& fields,
                        const std::function<bool()>& stop);

// The ended run in `work` (the closed file `written`) takes its name `out`, as publish_output with
// `add` when `with_fields` (a signal, SIGINT or SIGTERM, skips the fields), saying so on the
// terminal ("wrote OUT", the eigenmode XDMF files) and in `summary`; `code` is the run's exit code
// and `what` names the content in messages ("branch"). Returns the command's exit code: `code`, or
// 130 where a signal skipped the fields (`keller export OUT --xdmf` writes them). Throws a
// CommandFailure where a file could not be written or kept (exit 3) or for any other error (exit 4:
// CommandFailure::unexpected), the run staying in `work`, where the same command publishes it.
int publish_run(const std::string& work, const std::string& out, bool with_fields, const AddFields& add,
                const HeldFile& written, int code, const std::string& what, RunSummary& summary);
// The ended run that an earlier run of this command left in `work` (LeftRun::Kind::ended), killed
// before it took its name: published now with its exit code, as publish_run, saying so first.
// `summary` gets its reason and its cost, none of its own: a continuation of the output at its
// last row (RunSummary::continued_from).
int publish_left_run(const std::string& work, const std::string& out, bool with_fields, const AddFields& add,
                     const LeftRun& left, const std::string& what, RunSummary& summary);

}  // namespace keller
