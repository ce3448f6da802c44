#include "continuation/events/SpectrumScheduler.hpp"

#include <fmt/format.h>

#include "continuation/events/Bracket.hpp"

namespace keller {

namespace {
// Rounds of re-analysis that bring the reference point and the new one to one set of eigenvalues.
constexpr int kRecountRounds = 4;
}  // namespace

void SpectrumScheduler::restart(const BranchPoint& start, bool switched) {
  last_count_ = -1;
  last_count_row_ = -1;
  last_analysed_.reset();
  unanalysed_.clear();
  if (start.analysed && start.count >= 0 && !switched) {
    last_count_ = start.count;
    last_count_row_ = start.index;
    if (every() > 1) last_analysed_ = start;
  }
}

bool SpectrumScheduler::due(int step, int max_steps) const {
  // (the last step analyses its point too, so that no change of the count goes unchecked)
  return analysis_ && (step % every() == 0 || step >= max_steps);
}

std::optional<SpectrumScheduler::Change> SpectrumScheduler::change_at(
    BranchPoint& cur, BranchPoint& nxt, const std::function<void(BranchPoint&)>& analyse) {
  if (!analysis_ || !nxt.analysed || last_count_ < 0 || nxt.count < 0 || last_count_ == nxt.count) return std::nullopt;
  Change c;
  c.a = &cur;
  c.b = &nxt;
  c.from_row = last_count_row_;
  c.bracketed = last_count_row_ == cur.index;
  if (!c.bracketed && last_analysed_ && last_analysed_->index == last_count_row_ && !unanalysed_.empty() &&
      unanalysed_.back().index == cur.index) {
    std::vector<BranchPoint*> seq{&*last_analysed_};
    for (BranchPoint& q : unanalysed_) seq.push_back(&q);
    seq.push_back(&nxt);
    const int before = last_count_;
    const auto pair = bisect_change(seq.size(), 1, [&](size_t i) {
      analyse(*seq[i]);
      return seq[i]->count < 0 ? -1 : (seq[i]->count == before ? 1 : 0);
    });
    c.bracketed = pair.has_value();
    c.a = pair ? seq[pair->first] : seq.front();
    c.b = pair ? seq[pair->second] : &nxt;
  }
  c.this_step = c.a == &cur && c.b == &nxt;
  c.description = fmt::format("{} {} -> {}", analysis_->count_name(), c.a->count, c.b->count);
  return c;
}

std::optional<SpectrumScheduler::Recount> SpectrumScheduler::recount(BranchPoint& cur, BranchPoint& nxt,
                                                                     const std::function<void(BranchPoint&)>& analyse) {
  if (!analysis_ || !nxt.analysed || nxt.count < 0) return std::nullopt;
  BranchPoint* ref = every() > 1 ? (last_analysed_ ? &*last_analysed_ : nullptr) : (cur.analysed ? &cur : nullptr);
  if (!ref || ref->index != last_count_row_ || ref->count < 0) return std::nullopt;
  const int before = ref->count;
  // (the width only grows, to a cap: a few rounds at most)
  for (int round = 0; round < kRecountRounds && nxt.count >= 0 && ref->analysis_width != nxt.analysis_width; ++round) {
    if (nxt.analysis_width > ref->analysis_width) {
      const BranchPoint kept = *ref;
      analyse(*ref);
      if (ref->count < 0) {
        *ref = kept;
        break;
      }
    } else {
      analyse(nxt);
    }
  }
  if (ref->count == before) return std::nullopt;
  last_count_ = ref->count;
  return Recount{ref->index, before, ref->count};
}

void SpectrumScheduler::reported(const BranchPoint& p) {
  if (!analysis_) return;
  if (p.analysed && p.count >= 0) {
    last_count_ = p.count;
    last_count_row_ = p.index;
  }
  if (every() > 1) {
    if (p.analysed) {
      last_analysed_ = p;
      unanalysed_.clear();
    } else {
      unanalysed_.push_back(p);
    }
  }
}

}  // namespace keller
