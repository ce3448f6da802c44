// Newton's method with a backtracking line search on ||F||, built on the Problem interface and
// a SparseLU that keeps its symbolic analysis between solves (one numeric factorisation per
// iteration). Reports every iteration (residual, update, step length, time split) and ends with
// a Status: converged, or why not.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/Problem.hpp"
#include "core/Scene.hpp"
#include "core/SparseLU.hpp"

namespace keller {

struct NewtonOptions {
  int max_iterations = 20;  // iterations, chord ones (chord_rate) included
  // Converged when ||F||_inf <= residual_tolerance * problem.residual_scale(), or at the rounding
  // floor of the problem (ConvergenceTest: a full update below update_tolerance * max(||u||_inf, 1),
  // or a residual that stops falling, or that no damped step reduces, below the floor level).
  double residual_tolerance = 1e-10;
  double update_tolerance = 1e-12;
  bool line_search = true;
  double min_step_length = 1.0 / 128.0;  // smallest damping factor before giving up
  double divergence_factor = 1e8;        // give up when ||F|| exceeds this times its first value
  // Chord in the final phase (RenewalPolicy; 0: off, every iteration factorises): once a full step
  // has cut ||F|| by at least this factor, the next iterations solve with the same factorisation
  // while each cuts ||F|| by this factor; a new Jacobian as soon as one does not. A factorisation
  // costs tens of solves on large coupled problems, and the final phase of Newton contracts fast.
  double chord_rate = 0.25;
};

struct NewtonIteration {
  int iteration = 0;
  double residual_norm = 0;  // ||F||_inf at the start of the iteration
  double update_norm = 0;    // ||du||_inf of the full Newton step
  bool chord = false;        // solved with the previous iteration's factorisation
  double step_length = 1;    // damping factor taken
  double seconds = 0;        // wall time of this iteration
  double assembly_seconds = 0, factor_seconds = 0, solve_seconds = 0, line_search_seconds = 0;
};

struct NewtonResult {
  Status status;                   // Ok iff converged
  int iterations = 0;              // iterations done
  int factorisations = 0;          // Jacobian factorisations done (fewer with chord_rate)
  double residual_norm = 0;        // final ||F||_inf
  bool at_rounding_floor = false;  // converged at the problem's rounding floor, above the tolerance
  std::vector<NewtonIteration> history;
  double seconds = 0;
  double assembly_seconds = 0, factor_seconds = 0, solve_seconds = 0, line_search_seconds = 0;
  bool converged() const { return status.is_ok(); }
};

class NewtonSolver {
 public:
  using Observer = std::function<void(const NewtonIteration&)>;

  NewtonSolver(Problem& problem, NewtonOptions options = {}, SparseLUOptions lu_options = {});
  // Solves F(u) = 0 from the given u; on failure u holds the last accepted iterate. With
  // `on_kept`, the first iteration solves with the factorisation kept from the last solve (of a
  // nearby problem, such as the previous time step's matrix), renewed by the renewal policy like
  // any chord; without one (or without `on_kept`) it starts with a new Jacobian.
  NewtonResult solve(Vector& u, const Observer& observer = {}, bool on_kept = false);
  SparseLU& lu() { return *lu_; }
  // The last factorisation of J (shared: a continuation from the solution may keep it), the
  // Jacobian it factorises and the iterate where that was assembled.
  std::shared_ptr<SparseLU> factorisation() const { return lu_; }
  const SparseMatrix& jacobian() const { return J_; }
  const Vector& factorised_at() const { return J_at_; }
  const NewtonOptions& options() const { return options_; }
  // The iterative refinement steps of an iteration's solve (SparseLU::solve's argument; -1: the
  // LU options'): none on a chord iteration. Refinement makes the solve exact for the matrix
  // factorised, and a chord's error is that matrix's age, not the solve's rounding (the FSI orbit
  // of docs/periodic_orbits.md, 20 periods of evolve: the same 2,698 steps in half the time).
  static int refinement_steps(bool chord) { return chord ? 0 : -1; }

 private:
  Problem& problem_;
  NewtonOptions options_;
  std::shared_ptr<SparseLU> lu_;
  SparseMatrix J_;
  Vector J_at_;
  double floor_ = 0.0;  // rounding_floor() at the last assembled Jacobian
};

// Scene keys of [newton] and reading them back.
void declare_newton_keys(SceneSchema& schema);
NewtonOptions newton_options_from(const Scene& scene);

// Prints the Newton table header / rows to stdout.
void print_newton_header();
void print_newton_row(const NewtonIteration& it);

}  // namespace keller
