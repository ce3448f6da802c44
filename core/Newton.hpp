// Newton's method with a backtracking line search on ||F||, built on the Problem interface and
// a SparseLU that keeps its symbolic analysis between solves (one numeric factorisation per
// iteration). Reports every iteration (residual, update, step length, time split) and ends with
// a Status: converged, or why not.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/Problem.hpp"
#include "core/Scene.hpp"
#include "core/SparseLU.hpp"

namespace keller {

struct NewtonOptions {
  int max_iterations = 20;  // iterations, chord ones (chord_rate) included
  // Converged when ||F||_inf <= residual_tolerance * problem.residual_scale() ...
  double residual_tolerance = 1e-10;
  // ... or when a full step has ||du||_inf <= update_tolerance * max(||u||_inf, 1) and did not
  // increase the residual, or when no damped step reduces a residual that is already within
  // 1e3 of the tolerance (both: convergence to rounding level).
  double update_tolerance = 1e-12;
  bool line_search = true;
  double min_step_length = 1.0 / 128.0;  // smallest damping factor before giving up
  double divergence_factor = 1e8;        // give up when ||F|| exceeds this times its first value
  // Chord in the final phase (0: off, every iteration factorises): once a full step has cut ||F||
  // by at least this factor, the next iterations solve with the same factorisation while each
  // cuts ||F|| by this factor; a new Jacobian as soon as one does not.
  double chord_rate = 0.0;
};

struct NewtonIteration {
  int iteration = 0;
  double residual_norm = 0;   // ||F||_inf at the start of the iteration
  double update_norm = 0;     // ||du||_inf of the full Newton step
  bool chord = false;         // solved with the previous iteration's factorisation
  double step_length = 1;     // damping factor taken
  double seconds = 0;         // wall time of this iteration
  double assembly_seconds = 0, factor_seconds = 0, solve_seconds = 0, line_search_seconds = 0;
};

struct NewtonResult {
  Status status;                       // Ok iff converged
  int iterations = 0;                  // iterations done
  int factorisations = 0;              // Jacobian factorisations done (fewer with chord_rate)
  double residual_norm = 0;            // final ||F||_inf
  std::vector<NewtonIteration> history;
  double seconds = 0;
  double assembly_seconds = 0, factor_seconds = 0, solve_seconds = 0, line_search_seconds = 0;
  bool converged() const { return status.is_ok(); }
};

class NewtonSolver {
 public:
  using Observer = std::function<void(const NewtonIteration&)>;

  NewtonSolver(Problem& problem, NewtonOptions options = {}, SparseLUOptions lu_options = {});
  // Solves F(u) = 0 from the given u; on failure u holds the last accepted iterate.
  NewtonResult solve(Vector& u, const Observer& observer = {});
  SparseLU& lu() { return lu_; }
  const SparseMatrix& jacobian() const { return J_; }
  const NewtonOptions& options() const { return options_; }

 private:
  Problem& problem_;
  NewtonOptions options_;
  SparseLU lu_;
  SparseMatrix J_;
};

// Scene keys of [newton] and reading them back.
void declare_newton_keys(SceneSchema& schema);
NewtonOptions newton_options_from(const Scene& scene);

// Prints the Newton table header / rows to stdout.
void print_newton_header();
void print_newton_row(const NewtonIteration& it);

}  // namespace keller
