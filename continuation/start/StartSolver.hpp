// The first steady state of a run, found by itself: Newton from the problem's initial guess, and
// where that fails, continuation from a state Newton can solve. First along the problem's declared
// homotopy parameters (Problem::homotopies(): the first set to its easy value, and more of them as
// long as Newton fails there, from the scene's initial guess and from the problem's guess made at
// the easy values), continued back to their set values one after the other; then, or
// where the problem declares none, along the residual homotopy F(u) - (1 - s) F(u_guess) = 0 from
// s = 0 (the guess itself) to s = 1. Each stage is an ordinary branch of the continuation engine
// that ends exactly on its target value; a final Newton solve polishes the state. It says which path
// it took.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "core/Newton.hpp"
#include "core/Problem.hpp"
#include "core/Scene.hpp"
#include "core/SparseLU.hpp"

namespace keller {

struct StartOptions {
  // auto: Newton from the guess, then the problem's homotopy parameters, then the residual
  // homotopy; parameters / residual: that homotopy at once (without trying Newton from the guess
  // first); off: Newton from the guess only.
  enum class Path { Auto, Parameters, Residual, Off };
  Path path = Path::Auto;
  int max_steps = 200;  // continuation steps per stage

  static void declare(SceneSchema& schema);
  static StartOptions from_scene(const Scene& scene);
};

struct StartResult {
  Status status;     // ok: the vector solves F = 0 at the problem's parameter values
  std::string path;  // how it was reached, for people
  bool by_continuation = false;
  int newton_iterations = 0;  // of every Newton solve made
  long factorisations = 0;    // of every stage (Newton and continuation)
  int steps = 0;              // continuation points of every stage
  double seconds = 0.0;
  // J's last factorisation of the Newton solve that found the state, the Jacobian it factorises
  // and its iterate (null where that solve needed none): a branch from the state may start on it
  std::shared_ptr<SparseLU> factorisation;
  SparseMatrix jacobian;
  Vector factorised_at;
};

class StartSolver {
 public:
  using Say = std::function<void(const std::string&)>;
  StartSolver(Problem& problem, NewtonOptions newton, SparseLUOptions lu, StartOptions options = {}, Say say = {});
  // u: the initial guess in, the steady state out (where found; else the last Newton iterate from
  // the guess). first_newton: observer of the Newton iterations from the guess (the table).
  StartResult solve(Vector& u, const NewtonSolver::Observer& first_newton = {});
  // The continuation paths alone (after a Newton solve from the guess u that failed elsewhere).
  StartResult reach(Vector& u);

 private:
  // Newton at the present parameter values from u (u updated where it converged).
  bool newton(Vector& u, StartResult& r, const NewtonSolver::Observer& observer = {});
  // Continues the problem's parameter `name` from its present value to `target` from the
  // converged state u (u: the end state).
  bool continue_parameter(Problem& problem, const std::string& name, double target, Vector& u, StartResult& r,
                          std::string& why);
  bool by_parameters(const Vector& guess, Vector& u, StartResult& r);
  bool by_residual(const Vector& guess, Vector& u, StartResult& r);
  void say(const std::string& line) const;

  Problem& problem_;
  NewtonOptions newton_;
  SparseLUOptions lu_;
  StartOptions options_;
  Say say_;
};

}  // namespace keller
