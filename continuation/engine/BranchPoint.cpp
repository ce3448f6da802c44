#include "continuation/engine/BranchPoint.hpp"

namespace keller {

const char* to_string(PointKind k) {
  switch (k) {
    case PointKind::Regular: return "point";
    case PointKind::Start: return "start";
    case PointKind::Requested: return "stop";
    case PointKind::Event: return "event";
    case PointKind::Fold: return "fold";
    case PointKind::BranchPoint: return "bp";
    case PointKind::End: return "end";
    case PointKind::Hopf: return "hopf";
    case PointKind::PeriodDoubling: return "pd";
    case PointKind::NeimarkSacker: return "ns";
  }
  return "?";
}

}  // namespace keller
