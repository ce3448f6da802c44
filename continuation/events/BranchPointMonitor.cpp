#include "continuation/events/BranchPointMonitor.hpp"

#include "continuation/events/Bracket.hpp"

namespace keller {

void BranchPointMonitor::restart(const BranchPoint& start) {
  history_.assign(1, start);
  signed_ = 0;
  exact_ = true;
  sign_ = start.bordered_det_sign;
}

bool BranchPointMonitor::needs_probe(const BranchPoint& nxt, bool last) const {
  if (nxt.bordered_det_sign != 0 || sign_ == 0) return false;
  const size_t unsigned_rows = history_.size() - signed_;  // with nxt
  return last || unsigned_rows >= static_cast<size_t>(kBranchPointProbeRows);
}

std::optional<std::pair<BranchPoint, BranchPoint>> BranchPointMonitor::accepted(
    const BranchPoint& nxt, bool exact, const std::function<int(BranchPoint&)>& probe) {
  history_.push_back(nxt);
  const int s = nxt.bordered_det_sign;
  if (s == 0) return std::nullopt;
  std::optional<std::pair<BranchPoint, BranchPoint>> change;
  if (sign_ != 0 && s != sign_) {
    // The last sign belongs to its point if J was factorised there, else to an iterate of its
    // step, after the point before it (which then has the same sign: no change came between the
    // signs before): the bracket starts there.
    const size_t first = exact_ || signed_ == 0 ? signed_ : signed_ - 1;
    std::vector<BranchPoint> seq(history_.begin() + static_cast<long>(first), history_.end());
    seq.front().bordered_det_sign = sign_;
    const int before = sign_;
    // (1: the sign before the change, 0: the other one, -1: not known)
    const auto side = [&](size_t i) {
      const int v = probe(seq[i]);
      return v == before ? 1 : (v == -before ? 0 : -1);
    };
    const auto pair =
        seq.size() == 2 ? std::make_optional(std::make_pair(size_t{0}, size_t{1})) : bisect_change(seq.size(), 1, side);
    if (pair) change = std::make_pair(seq[pair->first], seq[pair->second]);
  }
  sign_ = s;
  exact_ = exact;
  // keep the point before the signed one (the next bracket may start there) and the signed one
  history_.erase(history_.begin(), history_.end() - std::min<long>(2, static_cast<long>(history_.size())));
  signed_ = history_.size() - 1;
  return change;
}

void BranchPointMonitor::reported(const BranchPoint& p) {
  if (!history_.empty() && history_.back().lambda == p.lambda && history_.back().s == p.s)
    history_.back().index = p.index;
}

}  // namespace keller
