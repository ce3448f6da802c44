// The last phase of a trace, and `keller export --xdmf`: a finished branch file gets the fields
// of its stored solutions and its critical eigenmodes, with XDMF files beside it for ParaView,
// without a moment at which a file on disk is damaged. The fields are added to a copy
// (TARGET.fields.part) that is renamed over the target; the XDMF files follow once it is there.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/SolutionFields.hpp"
#include "core/Types.hpp"

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
// target). Throws std::runtime_error on I/O errors, leaving `work` as it was.
PublishedBranch publish_output(const std::string& work, const std::string& target, const std::string& xdmf,
                               bool with_fields, const AddFields& add, const std::function<bool()>& stop);

// Puts the closed branch file `work` at `target` (they may be the same file), with fields and
// XDMF files when `with_fields`. `work` is removed once the target holds the branch (unless it
// is the target). `stop` is asked between stored solutions. Throws std::runtime_error on I/O
// errors, leaving `work` as it was.
PublishedBranch publish_branch(const std::string& work, const std::string& target, const std::string& xdmf,
                               bool with_fields, const FieldsAt& fields, const std::function<bool()>& stop);

}  // namespace keller
