// When the point analysis (the stability spectrum) runs along a branch, and where its count
// changed: every N-th accepted point (PointAnalysis::every) and the last one; a change of the count
// between two analysed points is bracketed by bisection over the accepted points since the last
// analysed one (analysing about log2(N) of them), so that it can be located on one step.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "continuation/engine/BranchPoint.hpp"
#include "core/PointAnalysis.hpp"

namespace keller {

class SpectrumScheduler {
 public:
  explicit SpectrumScheduler(const PointAnalysis* analysis) : analysis_(analysis) {}
  bool active() const { return analysis_ != nullptr; }
  int every() const { return analysis_ ? std::max(analysis_->every(), 1) : 0; }
  // A new branch from start (its analysis done, if any; a switched branch starts on the branch
  // point itself, where the count is either value: not a reference).
  void restart(const BranchPoint& start, bool switched);
  // Whether the point of step number `step` (counting from 1) is analysed.
  bool due(int step, int max_steps) const;

  struct Change {
    BranchPoint* a = nullptr;  // the analysed pair that brackets the change
    BranchPoint* b = nullptr;
    bool bracketed = false;   // false: it could not be narrowed to one step (the note says why)
    bool this_step = false;   // the pair is the step's own cur and nxt
    std::string description;  // "<count name> 0 -> 1"
    int from_row = -1;        // the row of the last analysed point before the change
  };
  // Whether the count changed at nxt (analysed) since the last analysed point; analyse(point)
  // analyses a point in between for the bisection.
  std::optional<Change> change_at(BranchPoint& cur, BranchPoint& nxt, const std::function<void(BranchPoint&)>& analyse);
  // Where the analysis widened at nxt (it computes more than when the reference, the last analysed
  // point, was analysed: the unstable eigenvalues had reached the edge of its set), the reference
  // is analysed again, and nxt again where that widened it further, until both come from one set,
  // so that the change between them is counted in one set. Returns the reference's row and its
  // count before and after where the count changed (a change before it was missed there). A
  // re-analysis that fails leaves the reference as it was.
  struct Recount {
    int row = -1, before = -1, after = -1;
  };
  std::optional<Recount> recount(BranchPoint& cur, BranchPoint& nxt, const std::function<void(BranchPoint&)>& analyse);
  // A point was reported (its index set).
  void reported(const BranchPoint& p);

 private:
  const PointAnalysis* analysis_;
  int last_count_ = -1, last_count_row_ = -1;  // the last analysed point's count and row
  // analysis every N > 1 points: the last analysed point and the accepted points after it
  std::optional<BranchPoint> last_analysed_;
  std::vector<BranchPoint> unanalysed_;
};

}  // namespace keller
