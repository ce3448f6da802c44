// Strong rows that tie an unknown to the rate of another: u_i = du_j/dt in the time-dependent
// form, so u_i = 0 at a steady state (the row's residual) and B(i, j) = -1 (B du/dt = -F reads
// -du_j/dt = -u_i). The kinematic condition of a moving boundary: the fluid velocity on a wall
// that moves is the wall's velocity, the rate of its node positions.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/Term.hpp"

namespace keller {

class RateConstraintTerm final : public Term {
 public:
  explicit RateConstraintTerm(std::string name) : name_(std::move(name)) {}
  // Row `dof` becomes u_dof = d u_rate_of / dt.
  void add(int dof, int rate_of) { pairs_.emplace_back(dof, rate_of); }

  std::string name() const override { return name_; }
  int num_items() const override { return static_cast<int>(pairs_.size()); }
  int local_size() const override { return 2; }
  int local_rows() const override { return 1; }
  bool owns_rows() const override { return true; }
  void item_dofs(int item, int* dofs) const override {
    dofs[0] = pairs_[static_cast<size_t>(item)].first;
    dofs[1] = pairs_[static_cast<size_t>(item)].second;
  }
  Status residual(int, const double* u, double* r) const override {
    r[0] = u[0];
    return {};
  }
  Status jacobian(int, const double* u, double* r, double* J) const override {
    r[0] = u[0];
    J[0] = 1.0;
    J[1] = 0.0;
    return {};
  }
  Status parameter_derivative(int, int, const double*, double* dr) const override {
    dr[0] = 0.0;
    return {};
  }
  // r = u_i is linear: its second and third derivatives are zero
  bool has_directional_derivative() const override { return true; }
  Status directional_derivative(int, const double*, int, const double* const*, const double* const*,
                                double* r) const override {
    r[0] = 0.0;
    return {};
  }
  bool has_mass() const override { return true; }
  Status mass(int, const double*, double* B) const override {
    B[0] = 0.0;
    B[1] = -1.0;
    return {};
  }
  Status rate(int, const double*, const double* udot, double* r) const override {
    r[0] = -udot[1];
    return {};
  }
  const std::vector<std::pair<int, int>>& pairs() const { return pairs_; }

 private:
  std::string name_;
  std::vector<std::pair<int, int>> pairs_;
};

}  // namespace keller
