#include "runs/StoredStart.hpp"

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <sstream>

#include "continuation/output/BranchFile.hpp"
#include "core/H5File.hpp"
#include "runs/OutputFile.hpp"
#include "runs/PointLabels.hpp"

namespace keller {

StoredStart parse_stored_start(const std::string& flag, const std::string& s) {
  const auto colon = s.rfind(':');
  if (colon == std::string::npos || colon == 0)
    throw std::invalid_argument(flag + " needs FILE.h5:ROW (ROW a number, 'last' or a label such as fold1), got '" + s +
                                "'");
  StoredStart r;
  r.flag = flag;
  r.file = s.substr(0, colon);
  r.switching = flag == "--switch";
  r.curve = flag == "--from";
  const std::string row = s.substr(colon + 1);
  if (is_point_label(row)) {
    r.label = row;
  } else if (row != "last") {
    size_t used = 0;
    long v = -1;
    try {
      v = std::stol(row, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != row.size() || row.empty() || v < 0 || v > 1'000'000'000)
      throw std::invalid_argument(flag + ": '" + row +
                                  "' is not a row number, 'last' or a located point's label (start, stop1, event1, "
                                  "fold1, bp1, hopf1, end; `keller info " +
                                  r.file + "` lists them)");
    r.row = static_cast<int>(v);
  }
  return r;
}

std::optional<double> StoredPoint::value_of(const std::string& parameter) const {
  if (parameter == table.parameter) return point.lambda;
  auto it = header.parameters.find(parameter);
  if (it == header.parameters.end()) return std::nullopt;
  return it->second;
}

std::vector<std::string> origin_refusals(const RunHeader& header, const LoadedScene& scene, const Problem& problem) {
  std::vector<std::string> refusals;
  if (header.problem != problem.name())
    refusals.push_back(fmt::format("it was made by problem '{}', this scene is '{}'", header.problem, problem.name()));
  if (header.physics.empty())
    refusals.push_back("it holds no record of its physics (written by an older keller)");
  else if (const std::string physics = scene.physics(); !records_agree(header.physics, physics, scene.defaults()))
    refusals.push_back("its physics differs: " + record_difference(header.physics, physics, scene.defaults()));
  return refusals;
}

void refuse_unless_forced(std::vector<std::string>& refusals, const std::string& where, bool force,
                          std::vector<std::string>& warnings) {
  for (const std::string& r : refusals) {
    if (!force) throw std::invalid_argument(fmt::format("{}: {}; pass --force to start from it anyway", where, r));
    warnings.push_back(fmt::format("{}: {} (--force)", where, r));
  }
  refusals.clear();
}

StoredPoint read_stored_start(const StoredStart& start, const LoadedScene& scene, const Problem& problem,
                              const std::string& parameter, std::vector<std::string>& warnings) {
  const std::string where = fmt::format("{} '{}'", start.flag, start.file);
  StoredPoint stored;
  {
    H5File f(start.file, H5File::Mode::Read);
    stored.header = read_run_header(f);
  }
  stored.table = read_branch_table(start.file);
  const int row = start.label.empty() ? start.row : row_of_label(stored.table, start.label, where);
  stored.point = read_branch_point(start.file, row);
  const BranchPoint& point = stored.point;
  std::vector<std::string> refusals = origin_refusals(stored.header, scene, problem);
  auto refuse = [&]() { refuse_unless_forced(refusals, where, start.force, warnings); };
  for (const Parameter& p : problem.parameters().list()) {
    if (p.name == parameter) continue;  // the run's own parameter starts at the point's value
    if (start.curve && p.name == stored.table.parameter) continue;  // an unknown of the curve
    const std::optional<double> v = stored.value_of(p.name);
    if (!v) continue;
    const double tol = 1e-12 * std::max({1.0, std::abs(*v), std::abs(p.value)});
    if (std::abs(*v - p.value) > tol)
      refusals.push_back(fmt::format("{} {} = {}, this scene sets {} = {}",
                                     p.name == stored.table.parameter ? "the point is at" : "it was traced at", p.name,
                                     *v, p.name, p.value));
  }
  refuse();
  if (point.u.size() != problem.size())
    throw std::invalid_argument(fmt::format("{}: the stored point has {} unknowns, this scene's problem {}", where,
                                            point.u.size(), problem.size()));
  if (start.switching && stored.table.parameter != parameter)
    throw std::invalid_argument(fmt::format("{}: a branch in '{}' cannot be switched to a branch in '{}'", where,
                                            stored.table.parameter, parameter));
  if (start.curve && stored.table.parameter == parameter)
    throw std::invalid_argument(
        fmt::format("{}: the curve of a point of a branch in '{}' needs another free parameter "
                    "than '{}' (--free)",
                    where, parameter, parameter));
  // the located point the start needs: a branch point (--switch), the curve's or orbit branch's kind
  // (--from; --switch with --orbit: a period doubling)
  const PointKind required = start.switching && !start.orbit ? PointKind::BranchPoint : start.located;
  const bool event_curve = required == PointKind::Event;
  auto wanted = [&](int k) {
    return event_curve ? k == static_cast<int>(PointKind::Event) || k == static_cast<int>(PointKind::End)
                       : k == static_cast<int>(required);
  };
  if ((start.switching || start.curve || start.orbit) && !wanted(static_cast<int>(point.kind))) {
    std::string located;
    const BranchTable& table = stored.table;
    const int kind = table.column("kind");
    for (int r : table.saved_rows)
      if (r < table.rows.rows() && wanted(static_cast<int>(table.rows(r, kind))))
        located += (located.empty() ? "" : ", ") + std::to_string(r);
    const std::string what = event_curve                             ? "event"
                             : required == PointKind::BranchPoint    ? "branch point"
                             : required == PointKind::Hopf           ? "Hopf point"
                             : required == PointKind::PeriodDoubling ? "period doubling"
                                                                     : "fold";
    refusals.push_back(fmt::format("row {} is not a located {} (located {}s with a stored solution: {})", point.index,
                                   what, what, located.empty() ? "none" : located));
  }
  refuse();
  return stored;
}

}  // namespace keller
