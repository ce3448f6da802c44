#include "runs/TraceStart.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "runs/BranchStarts.hpp"
#include "runs/CommandRun.hpp"
#include "runs/CurveStarts.hpp"

namespace keller {

TraceSettings TraceSettings::from_scene(const Scene& scene, const std::string& free) {
  TraceSettings s;
  s.continuation = ContinuationOptions::from_scene(scene);
  s.stability = StabilityOptions::from_scene(scene);
  if (!free.empty()) s.continuation.parameter = free;
  s.newton = newton_options_from(scene);
  s.lu = sparse_lu_options_from(scene);
  s.start = StartOptions::from_scene(scene);
  return s;
}

TraceSource read_trace_source(const CommandRun& run, const std::string& record, bool fresh,
                              const std::optional<StoredStart>& from, const Problem& problem,
                              const std::string& parameter) {
  TraceSource source;
  BranchTable table;
  source.left = run.left(record, fresh, [&](const std::string& path) {
    table = read_branch_table(path);
    return std::pair<long, std::string>(table.rows.rows(), table.status);
  });
  if (source.left.kind == LeftRun::Kind::ended) return source;
  if (source.left.kind == LeftRun::Kind::unfinished) {
    Unfinished& u = source.unfinished.emplace();
    u.file = run.work();
    u.seed = read_branch_seed(u.file);
    u.point = read_branch_point(u.file, u.seed.row);
    u.state_scale = table.state_scale;
    u.theta = table.theta;
  }
  if (!from || (source.unfinished && !from->curve)) return source;
  const StoredPoint& stored =
      source.stored.emplace(read_stored_start(*from, run.loaded(), problem, parameter, source.warnings));
  // a new branch (or curve) in another parameter starts at the point's value of it
  if (!source.unfinished && stored.table.parameter != parameter && !stored.value_of(parameter))
    throw std::invalid_argument(
        fmt::format("{}: '{}' does not record the value of '{}'", from->flag, from->file, parameter));
  return source;
}

TraceStart trace_start(Problem& problem, const TraceSettings& settings, const std::optional<StoredStart>& from,
                       const TraceSource& source, const Scene& scene, int direction) {
  const Unfinished* unfinished = source.unfinished ? &*source.unfinished : nullptr;
  TraceStart start;
  if (from && from->curve && from->located == PointKind::Event)
    start = start_event_curve(problem, settings, *from, *source.stored, unfinished);
  else if (from && from->curve && from->located == PointKind::Hopf)
    start = start_hopf_curve(problem, settings, *from, *source.stored, unfinished);
  else if (from && from->curve)
    start = start_fold_curve(problem, settings, *from, *source.stored, unfinished);
  else if (unfinished)
    start = continue_unfinished(problem, settings, *unfinished);
  else if (!from)
    start = start_fresh(problem, settings);
  else if (source.stored->table.parameter != settings.continuation.parameter)
    start = start_in_other_parameter(problem, settings, *from, *source.stored, scene);
  else
    start = start_at_point(problem, settings, *from, *source.stored, direction);
  if (!(start.options.state_scale > 0)) {  // a new run's state scale is the RMS of its start
    const Vector& u0 = start.state;
    const double rms = u0.norm() / std::sqrt(static_cast<double>(std::max<long>(u0.size(), 1)));
    start.options.state_scale = rms > 0 ? rms : 1.0;
  }
  return start;
}

void use_stored_parameters(Problem& problem, const StoredPoint& stored) {
  for (const Parameter& q : problem.parameters().list())
    if (const auto v = stored.value_of(q.name)) problem.parameters().set(q.name, *v);
}

void say_continuing(const std::string& what, const Unfinished& unfinished, const std::string& parameter) {
  fmt::print("continuing the unfinished {} in {} from its row {} ({} = {:.10g}; --fresh starts over)\n", what,
             unfinished.file, unfinished.seed.row, parameter, unfinished.point.lambda);
}

}  // namespace keller
