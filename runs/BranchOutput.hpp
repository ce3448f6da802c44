// The last phase of a trace, and `keller export --xdmf`: a finished branch file gets the fields
// of its stored solutions and its critical eigenmodes, with XDMF files beside it for ParaView,
// without a moment at which a file on disk is damaged. The fields are added to a copy
// (TARGET.fields.part) that is renamed over the target; the XDMF files follow once it is there.
#pragma once

#include <functional>
#include <string>

#include "core/SolutionFields.hpp"
#include "core/Types.hpp"

namespace keller {

using FieldsAt = std::function<SolutionFields(const Vector& u, double lambda)>;

struct PublishedBranch {
  bool fields = false;  // false: `stop` interrupted the fields (the branch is at the target without them)
  int modes = 0;        // eigenmode XDMF files written
};

// Puts the closed branch file `work` at `target` (they may be the same file), with fields and
// XDMF files when `with_fields`. `work` is removed once the target holds the branch (unless it
// is the target). `stop` is asked between stored solutions. Throws std::runtime_error on I/O
// errors, leaving `work` as it was.
PublishedBranch publish_branch(const std::string& work, const std::string& target, const std::string& xdmf,
                               bool with_fields, const FieldsAt& fields, const std::function<bool()>& stop);

}  // namespace keller
