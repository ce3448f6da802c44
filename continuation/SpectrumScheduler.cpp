#include "continuation/SpectrumScheduler.hpp"

#include <fmt/format.h>

#include "continuation/Bracket.hpp"

namespace keller {

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
