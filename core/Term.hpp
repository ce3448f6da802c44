// One kind of local contribution to a global residual: an element kernel over a set of
// elements, a boundary kernel over boundary edges, or a strong (row-replacing) constraint such
// as a Dirichlet condition. The Assembler sums terms into F and J without knowing any physics.
//
// Each item (element, edge, constrained node) touches local_size() global unknowns; it writes
// residual rows for the first local_rows() of them. A term that owns_rows() replaces those rows
// entirely: weak (integrated) contributions to them are dropped, or redirected elsewhere when
// the Assembler is told to (the consistent reaction force at a fluid-solid interface).
#pragma once

#include <string>

#include "core/Status.hpp"

namespace keller {

class Term {
 public:
  virtual ~Term() = default;
  virtual std::string name() const = 0;
  virtual int num_items() const = 0;
  virtual int local_size() const = 0;
  virtual int local_rows() const { return local_size(); }
  virtual bool owns_rows() const { return false; }
  // Global unknown indices of an item (local_size() entries, all >= 0).
  virtual void item_dofs(int item, int* dofs) const = 0;
  // r (local_rows()) at the item's unknown values u (local_size()).
  virtual Status residual(int item, const double* u, double* r) const = 0;
  // r and dr/du, row-major local_rows() x local_size().
  virtual Status jacobian(int item, const double* u, double* r, double* J) const = 0;
  // dr/dp for parameter index p of the problem's ParameterSet.
  virtual Status parameter_derivative(int item, int p, const double* u, double* dr) const = 0;
  // Whether the item's equations carry time derivatives: B du/dt = -F (B row-major like J).
  virtual bool has_mass() const { return false; }
  virtual Status mass(int item, const double* u, double* B) const { return {}; }
  // The time terms of the item's rows, r = B(u) udot (local_rows()): the part of the
  // time-dependent residual B du/dt + F that holds the time derivatives. The default multiplies
  // mass() out; a term that writes them directly (KernelTerm) evaluates them without forming B.
  virtual Status rate(int item, const double* u, const double* udot, double* r) const;
  // r = residual + rate at once: the item's rows of the time-dependent residual B(u) udot + F(u)
  // (Assembler::time_dependent_residual). The default calls the two; a KernelTerm whose kernel
  // evaluates both together (sharing a moving element's geometry) takes that.
  virtual Status residual_with_rate(int item, const double* u, const double* udot, double* r) const;
  // The order-th directional derivative of r (order 2 or 3), D^k r[d_1, ..., d_k] (local_rows()),
  // each direction d_j a change du[j] of the item's unknowns (local_size()) and dp[j] of the
  // problem's parameters (its ParameterSet's size; null: none), for normal forms
  // (core/ExactDerivatives.hpp). has_directional_derivative(): whether the term offers it exactly;
  // the default offers nothing and its directional_derivative throws std::logic_error.
  virtual bool has_directional_derivative() const { return false; }
  virtual Status directional_derivative(int item, const double* u, int order, const double* const* du,
                                        const double* const* dp, double* r) const;
};

}  // namespace keller
