// Small problems with known answers for testing the continuation engine, and an observer that
// keeps the branch in memory.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "continuation/Continuation.hpp"
#include "core/Problem.hpp"

namespace keller::test {

// F(u, lambda) = u^3 - 3u - lambda (one unknown): folds at (u, lambda) = (-1, 2) and (1, -2).
// Observable "u"; monitor "u - 1/2" (zero at lambda = 1/8 - 3/2 = -1.375).
class CubicProblem final : public Problem {
 public:
  explicit CubicProblem(double lambda);
  std::string name() const override { return "cubic"; }
  int size() const override { return 1; }
  ParameterSet& parameters() override { return params_; }
  const ParameterSet& parameters() const override { return params_; }
  const SparseMatrix& jacobian_pattern() const override { return pattern_; }
  Status residual(const Vector& u, Vector& F) override;
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override;
  Status parameter_derivative(int p, const Vector& u, Vector& dF) override;
  Vector initial_guess() override { return Vector::Constant(1, -2.0); }
  std::vector<std::string> observable_names() const override { return {"u"}; }
  Status observables(const Vector& u, std::vector<double>& v) override;
  std::vector<std::string> monitor_names() const override { return {"u - 1/2"}; }
  Status monitors(const Vector& u, std::vector<double>& v) override;
  SolutionFields fields(const Vector&) const override { return {}; }

 private:
  ParameterSet params_;
  SparseMatrix pattern_;
};

// A small dense problem given by functions of the state u and the parameter values p: F(u, p),
// its exact Jacobian and dF/dp_k (normal forms, closed-form curves), with named parameters, the
// mass matrix B = I (B du/dt = -F) and optional monitors (the zero-based parameter index k).
class FunctionProblem final : public Problem {
 public:
  using Residual = std::function<Vector(const Vector& u, const Vector& p)>;
  using Jacobian = std::function<Eigen::MatrixXd(const Vector& u, const Vector& p)>;
  using ParameterDerivative = std::function<Vector(int k, const Vector& u, const Vector& p)>;
  using Monitors = std::function<std::vector<double>(const Vector& u)>;
  FunctionProblem(std::string name, int n, const std::vector<std::pair<std::string, double>>& parameters, Residual F,
                  Jacobian J, ParameterDerivative Fp);
  // Monitors by name (their values at a state).
  void set_monitors(std::vector<std::string> names, Monitors m);

  std::string name() const override { return name_; }
  int size() const override { return n_; }
  ParameterSet& parameters() override { return params_; }
  const ParameterSet& parameters() const override { return params_; }
  const SparseMatrix& jacobian_pattern() const override { return pattern_; }
  Status residual(const Vector& u, Vector& F) override;
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override;
  Status parameter_derivative(int p, const Vector& u, Vector& dF) override;
  Status mass_matrix(const Vector& u, SparseMatrix& B) override;
  Vector initial_guess() override { return Vector::Zero(n_); }
  std::vector<std::string> monitor_names() const override { return monitor_names_; }
  Status monitors(const Vector& u, std::vector<double>& v) override;
  SolutionFields fields(const Vector&) const override { return {}; }

 private:
  Vector values() const;
  std::string name_;
  int n_;
  ParameterSet params_;
  SparseMatrix pattern_;
  Residual F_;
  Jacobian J_;
  ParameterDerivative Fp_;
  std::vector<std::string> monitor_names_;
  Monitors monitors_;
};

// The Brusselator ODE x' = a - (b + 1) x + x^2 y, y' = b x - x^2 y as B du/dt = -F (B = I), with
// parameters a, b (indices 0, 1): its Hopf point is at b = 1 + a^2, its orbits beyond it.
FunctionProblem brusselator_ode(double a, double b);

// Wraps a problem and reports an invalid state whenever the parameter lies in [a, b] (a model
// of a region where the physics breaks down).
class FailingBand final : public Problem {
 public:
  FailingBand(std::unique_ptr<Problem> inner, double a, double b) : inner_(std::move(inner)), a_(a), b_(b) {}
  std::string name() const override { return "failing-" + inner_->name(); }
  int size() const override { return inner_->size(); }
  ParameterSet& parameters() override { return inner_->parameters(); }
  const ParameterSet& parameters() const override { return inner_->parameters(); }
  const SparseMatrix& jacobian_pattern() const override { return inner_->jacobian_pattern(); }
  Status residual(const Vector& u, Vector& F) override;
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override;
  Status parameter_derivative(int p, const Vector& u, Vector& dF) override {
    return inner_->parameter_derivative(p, u, dF);
  }
  Vector initial_guess() override { return inner_->initial_guess(); }
  std::vector<std::string> observable_names() const override { return inner_->observable_names(); }
  Status observables(const Vector& u, std::vector<double>& v) override { return inner_->observables(u, v); }
  SolutionFields fields(const Vector& u) const override { return inner_->fields(u); }

 private:
  Status check() const;
  std::unique_ptr<Problem> inner_;
  double a_, b_;
};

// Bratu from lambda = 0 up its lower branch, through the fold, until the observable `stop`
// exceeds `above` on the upper branch.
ContinuationOptions bratu_fold_options(const std::string& stop, double above);

// The trivial branch u = 0 of the pitchfork problem from lambda = 1 to 45, through its first two
// branch points.
ContinuationOptions pitchfork_trivial_options();

// Keeps every reported point, rejection and note.
class RecordingObserver final : public BranchObserver {
 public:
  void on_point(const BranchPoint& p) override { points.push_back(p); }
  void on_rejected(double lambda, double step, const Status& why) override { rejections.push_back(why.describe()); }
  void on_note(const std::string& m) override { notes.push_back(m); }
  void on_finish(const std::string& r, const BranchPoint&) override { reason = r; }
  std::vector<const BranchPoint*> of_kind(PointKind k) const;
  std::vector<BranchPoint> points;
  std::vector<std::string> rejections, notes;
  std::string reason;
};

}  // namespace keller::test
