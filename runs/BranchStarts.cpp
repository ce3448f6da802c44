#include "runs/BranchStarts.hpp"

#include <fmt/format.h>

#include "runs/CommandFailure.hpp"

namespace keller {

TraceStart start_fresh(Problem& problem, const TraceSettings& settings) {
  const std::string& parameter = settings.continuation.parameter;
  StartSolver solver(problem, settings.newton, settings.lu, settings.start,
                     [](const std::string& line) { fmt::print("{}\n", line); });
  TraceStart start;
  start.options = settings.continuation;
  start.state = problem.initial_guess();
  fmt::print("first steady state at {} = {}\n", parameter, problem.parameters().get(parameter));
  print_newton_header();
  const StartResult r = solver.solve(start.state, print_newton_row);
  if (!r.status.is_ok()) throw CommandFailure::numerical("the first steady state failed", r.status);
  fmt::print("first steady state: {}, {} Newton iterations, {} factorisations, {:.2f} s\n", r.path, r.newton_iterations,
             r.factorisations, r.seconds);
  start.factorisation = {r.factorisation, r.jacobian, r.factorised_at};
  return start;
}

TraceStart continue_unfinished(Problem& problem, const TraceSettings& settings, const Unfinished& unfinished) {
  TraceStart start;
  start.begin = TraceStart::Begin::Point;
  start.point = unfinished.point;
  start.seed = unfinished.seed;
  start.options = settings.continuation;
  start.options.state_scale = unfinished.state_scale;
  start.options.theta = unfinished.theta;
  problem.parameters().set(start.options.parameter, unfinished.point.lambda);
  say_continuing("branch", unfinished, start.options.parameter);
  return start;
}

TraceStart start_at_point(Problem& problem, const TraceSettings& settings, const StoredStart& from,
                          const StoredPoint& stored, int direction) {
  TraceStart start;
  start.begin = from.switching ? TraceStart::Begin::Switch : TraceStart::Begin::Point;
  start.point = stored.point;
  start.direction = direction;
  start.options = settings.continuation;
  start.options.state_scale = stored.table.state_scale;
  start.options.theta = stored.table.theta;
  problem.parameters().set(start.options.parameter, stored.point.lambda);
  fmt::print("{} row {} of {} ({} = {:.10g})\n", from.switching ? "switching branches at" : "restarting from",
             stored.point.index, from.file, start.options.parameter, stored.point.lambda);
  return start;
}

TraceStart start_in_other_parameter(Problem& problem, const TraceSettings& settings, const StoredStart& from,
                                    const StoredPoint& stored, const Scene& scene) {
  const std::string& parameter = settings.continuation.parameter;
  const double lambda = *stored.value_of(parameter);
  use_stored_parameters(problem, stored);
  TraceStart start;
  start.state = stored.point.u;
  start.options = settings.continuation;
  fmt::print("starting a branch in {} at row {} of {}, a branch in {} ({} = {:.10g}, {} = {:.10g})\n", parameter,
             stored.point.index, from.file, stored.table.parameter, stored.table.parameter, stored.point.lambda,
             parameter, lambda);
  const std::string key = "parameters." + parameter;
  if (scene.schema().find(key) && scene.real(key) != lambda)
    fmt::print("note: {} starts at the stored point's value {:.10g}, not at the scene's {}\n", parameter, lambda,
               scene.real(key));
  return start;
}

}  // namespace keller
