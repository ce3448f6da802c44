// The problem contract: F(u, lambda) = 0 with named parameters, what a user implements to have
// keller solve, continue, analyse and integrate a problem. Everything above core/ (Newton,
// continuation, stability, the command-line driver) sees a problem only through this page.
//
// Sign convention: the time-dependent form is B du/dt = -F(u), so a steady state is F = 0 and the
// linear stability problem is J phi = sigma B phi with growth rate -sigma.
//
// Parameters are the problem's own (parameters()); the algorithms set them before they evaluate,
// so every evaluation below is at the parameters' present values. Numerical failure (a NaN, an
// inverted element) is a returned Status the algorithms react to; misuse throws.
//
// Required: name, size, parameters, jacobian_pattern, residual, initial_guess.
// Everything else has a default, and the defaults say what they cost. Beyond this page, a problem
// may offer gradients of its monitors and observables (core/MonitorGradients.hpp).
#pragma once

#include <stdexcept>
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

  // --- What the problem is (required) ---

  virtual std::string name() const = 0;
  // Number of unknowns; fixed for the lifetime of the object.
  virtual int size() const = 0;
  // The named parameters (ParameterSet: value, admissible range, doc), owned by the problem.
  virtual ParameterSet& parameters() = 0;
  virtual const ParameterSet& parameters() const = 0;
  // Sparsity pattern of the Jacobian (values unused). Fixed for the lifetime of the object, so a
  // symbolic factorisation is done once per branch.
  virtual const SparseMatrix& jacobian_pattern() const = 0;

  // --- The equations ---

  // F(u) (required).
  virtual Status residual(const Vector& u, Vector& F) = 0;
  // F(u) and J = dF/du (J takes the structure of jacobian_pattern()). Default: one-sided finite
  // differences column by column, one residual per column: for small problems only.
  virtual Status jacobian(const Vector& u, Vector& F, SparseMatrix& J);
  // dF/dp for parameter index p (parameters().index(name)). Default: central differences, two
  // residuals, the step kept inside the parameter's range.
  virtual Status parameter_derivative(int p, const Vector& u, Vector& dF);

  // --- The time terms (stability analysis, time integration) ---

  // Mass matrix B of B du/dt = -F (structure of jacobian_pattern(); rows without a time
  // derivative are zero). Default: throws NoTimeForm, a problem without dynamics has no B.
  virtual Status mass_matrix(const Vector& u, SparseMatrix& B);
  // The time terms of the time-dependent residual B(u) du/dt + F(u): R = B(u) udot, at every
  // residual of a time step. Default: forms B and multiplies (a problem assembled from terms
  // evaluates them directly).
  virtual Status time_residual(const Vector& u, const Vector& udot, Vector& R);
  // Why B is zero at the parameters' present values although the problem has a time-dependent
  // form (a Newtonian flow at Re = 0: Stokes flow has no time derivative), naming the parameter
  // that gives it one; empty where B has rows with a time derivative. A run that needs B there (a
  // spectrum of a steady state, a time integration) refuses its scene with it. Default: empty.
  virtual std::string why_no_time_derivative() const { return {}; }

  // --- Starting and scaling ---

  // A starting guess consistent with the boundary conditions (required).
  virtual Vector initial_guess() = 0;
  // Typical size of F entries for a solution of unit scale; Newton's residual tolerance is
  // relative to it (velocities scale with Gamma in the channel problems). Default: 1.
  virtual double residual_scale() const { return 1.0; }
  // Parameters in which a steady state that Newton cannot reach from initial_guess() is reached by
  // continuation from an easier one: each with a value where the solve is easy (a load near rest,
  // a relaxation time near zero), in the order to try them. Default: none, only the generic
  // residual homotopy (continuation/start/StartSolver).
  struct Homotopy {
    std::string parameter;
    double easy_value = 0.0;
  };
  virtual std::vector<Homotopy> homotopies() const { return {}; }

  // --- What is computed from a solution ---

  // Observables: named scalars in the branch table (pressure drop, max u, ...); a run may stop
  // where one crosses a threshold. Default: none.
  virtual std::vector<std::string> observable_names() const { return {}; }
  virtual Status observables(const Vector& u, std::vector<double>& values);
  // Monitors: named functions whose sign changes along a branch are events, located and labelled.
  // Default: none.
  virtual std::vector<std::string> monitor_names() const { return {}; }
  virtual Status monitors(const Vector& u, std::vector<double>& values);
  // Fields of a solution for the output files (HDF5, XDMF). Default: none (the state vector
  // alone is stored).
  virtual SolutionFields fields(const Vector& u) const;
  // One line on what the discretisation is ("Q2-P1disc, 320 elements, 8210 unknowns"). Default:
  // name().
  virtual std::string summary() const { return name(); }
};

// What mass_matrix throws for a problem without a time-dependent form (the default): a run that
// needs one (a spectrum, a time integration) asks has_time_form() first and refuses its scene.
class NoTimeForm : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

// Whether the problem has a time-dependent form: mass_matrix gives B instead of throwing
// NoTimeForm (one assembly of B), at the state u. Without u, at its initial guess: only where no
// state is at hand, since a problem's initial guess need not exist at every parameter value (an
// algebraic guess past the fold where its root turns complex).
bool has_time_form(Problem& problem, const Vector& u);
bool has_time_form(Problem& problem);

// G = F(u) + B(u) udot, the time-dependent residual at the rate udot (every chord iteration of a
// time step, two in every product of the shooting map's linearised passes): residual plus
// time_residual, or for a problem assembled from terms (AssembledProblem) both in one pass over
// its elements, which shares what the two compute alike (a moving element's geometry). Throws
// NoTimeForm where the problem has no time-dependent form.
Status time_dependent_residual(Problem& problem, const Vector& u, const Vector& udot, Vector& G);

// What a run that needs B says to refuse a problem that has none as its scene sets it up: empty
// where it has a time-dependent form with a time derivative at the parameters' present values;
// else why (no time-dependent form at all, or why_no_time_derivative()).
std::string time_form_refusal(Problem& problem);
// The same at the state u (has_time_form(problem, u)).
std::string time_form_refusal(Problem& problem, const Vector& u);

}  // namespace keller
