// A problem written in Python (a keller.Problem subclass: python/keller/problem.py, docs/python.md)
// behind keller's problem contract (core/Problem.hpp), so that the C++ engine continues it with
// every capability: each method of the contract calls the Python method of the same name, with the
// GIL held only for that call. The optional methods a Python class does not define get the C++
// defaults (finite-difference Jacobian over jacobian_pattern, central-difference dF/dp, no B).
//
// Arrays: u goes to Python as a new float64 array (the engine's vector is not lent out); F, dF/dp
// and the observables come back as sequences of the right length; J and B as any scipy.sparse
// matrix (or a dense one), taken into jacobian_pattern()'s structure: a matrix with exactly that
// CSC structure is copied as it is, another is scattered into it, and an entry outside it is a
// ValueError. A Python exception is raised again by the keller.* call that ran the problem, after the
// command has stopped (keeping what it completed); keller.NumericalFailure is a failed evaluation
// instead (a state outside the model's domain), to which Newton and the step control react.
#pragma once

#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "core/Problem.hpp"

namespace keller::python {

class PythonProblem final : public Problem {
 public:
  explicit PythonProblem(pybind11::object problem);  // the GIL is acquired here
  ~PythonProblem() override;

  std::string name() const override { return name_; }
  int size() const override { return size_; }
  ParameterSet& parameters() override { return params_; }
  const ParameterSet& parameters() const override { return params_; }
  const SparseMatrix& jacobian_pattern() const override { return pattern_; }

  Status residual(const Vector& u, Vector& F) override;
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override;
  Status parameter_derivative(int p, const Vector& u, Vector& dF) override;
  Status mass_matrix(const Vector& u, SparseMatrix& B) override;
  Vector initial_guess() override;
  double residual_scale() const override { return residual_scale_; }
  std::vector<std::string> observable_names() const override { return observable_names_; }
  Status observables(const Vector& u, std::vector<double>& values) override;
  std::vector<std::string> monitor_names() const override { return monitor_names_; }
  Status monitors(const Vector& u, std::vector<double>& values) override;
  std::string summary() const override { return summary_; }

 private:
  pybind11::dict parameter_dict() const;  // {name: value} at the present values (GIL held)
  pybind11::object call(const char* method, const Vector& u);
  template <class Body>
  Status guarded(const char* method, Body&& body);

  pybind11::object obj_, failure_type_, sparse_parts_;
  std::string name_, summary_;
  int size_ = 0;
  double residual_scale_ = 1.0;
  bool has_jacobian_ = false, has_dfdp_ = false, has_mass_ = false;
  ParameterSet params_;
  SparseMatrix pattern_;
  std::vector<std::string> observable_names_, monitor_names_;
};

// The problem that scenes of type "python" build while a keller.* call runs (the problem= argument),
// or none (None): set for the call's duration.
class CurrentProblem {
 public:
  explicit CurrentProblem(pybind11::object problem);
  ~CurrentProblem();
  CurrentProblem(const CurrentProblem&) = delete;
  CurrentProblem& operator=(const CurrentProblem&) = delete;
};

// Registers the problem type "python" (its scene keys: parameters.<name> of the current problem,
// defaulting to its values). Once, at the module's import.
void register_python_type();

// A Python exception raised while a command ran (in a problem's method or a run's callback), kept
// to be raised again when the command has returned: the first one is kept.
void keep_exception(pybind11::error_already_set& e);
// Raises the kept exception, if any (GIL held).
void raise_kept_exception();

}  // namespace keller::python
