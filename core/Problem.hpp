// The problem interface: F(u, lambda) = 0 with named parameters. Everything above core/
// (Newton, continuation, stability, the command-line driver) sees problems only through this.
//
// Sign convention: the time-dependent form is B du/dt = -F(u), so a steady state is F = 0 and
// the linear stability problem is J phi = sigma B phi with growth rate -sigma.
#pragma once

#include <string>
#include <vector>

#include "core/ParameterSet.hpp"
#include "core/SolutionFields.hpp"
#include "core/Status.hpp"
#include "core/Types.hpp"

namespace keller {

class Problem {
 public:
  virtual ~Problem() = default;

  virtual std::string name() const = 0;
  // Number of unknowns; fixed for the lifetime of the object.
  virtual int size() const = 0;
  virtual ParameterSet& parameters() = 0;
  virtual const ParameterSet& parameters() const = 0;
  // Sparsity pattern of the Jacobian (values unused). Fixed for the lifetime of the object, so a
  // symbolic factorisation is done once per branch.
  virtual const SparseMatrix& jacobian_pattern() const = 0;

  // F(u) at the current parameter values.
  virtual Status residual(const Vector& u, Vector& F) = 0;
  // F(u) and J = dF/du (J takes the structure of jacobian_pattern()). The default takes
  // one-sided finite differences column by column: acceptable for small problems only.
  virtual Status jacobian(const Vector& u, Vector& F, SparseMatrix& J);
  // dF/dp for parameter index p. The default takes central differences.
  virtual Status parameter_derivative(int p, const Vector& u, Vector& dF);
  // Mass matrix B of B du/dt = -F (structure of jacobian_pattern(); rows without a time
  // derivative are zero). The default throws: a problem without dynamics has no B.
  virtual Status mass_matrix(const Vector& u, SparseMatrix& B);
  // The time terms of the time-dependent residual B(u) du/dt + F(u): R = B(u) udot. The default
  // forms B; problems assembled from terms evaluate them directly (a time step needs them at
  // every residual, B only with the Jacobian).
  virtual Status time_residual(const Vector& u, const Vector& udot, Vector& R);

  // A starting guess consistent with the boundary conditions.
  virtual Vector initial_guess() = 0;
  // Typical size of F entries for a solution of unit scale; Newton's residual tolerance is
  // relative to it (velocities scale with Gamma in the channel problems).
  virtual double residual_scale() const { return 1.0; }

  // Parameters in which a steady state that Newton cannot reach from initial_guess() is reached by
  // continuation from an easier one: each with a value where the solve is easy (a load near rest,
  // a relaxation time near zero), in the order to try them. Empty: only the generic residual
  // homotopy (continuation/start/StartSolver).
  struct Homotopy {
    std::string parameter;
    double easy_value = 0.0;
  };
  virtual std::vector<Homotopy> homotopies() const { return {}; }

  // Observables: named scalars computed from a solution (pressure drop, max u, ...).
  virtual std::vector<std::string> observable_names() const { return {}; }
  virtual Status observables(const Vector& u, std::vector<double>& values);
  // Monitors: named functions whose sign changes along a branch are events.
  virtual std::vector<std::string> monitor_names() const { return {}; }
  virtual Status monitors(const Vector& u, std::vector<double>& values);
  // Fields of a solution for output.
  virtual SolutionFields fields(const Vector& u) const = 0;
  // One line on what the discretisation is ("Q2-P1disc, 320 elements, 8210 unknowns").
  virtual std::string summary() const { return name(); }
};

}  // namespace keller
