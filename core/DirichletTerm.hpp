// Strong Dirichlet conditions: the row of each constrained unknown u_i is replaced by
// u_i - g_i(parameters) = 0. Values g_i are functions of the problem's parameters (an inflow
// profile scales with the flow rate), so dF/dp = -dg_i/dp, taken by central differences of g,
// which is exact to rounding for the affine dependence of every boundary value in this project.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/ParameterSet.hpp"
#include "core/Term.hpp"

namespace keller {

class DirichletTerm final : public Term {
 public:
  using ValueFunction = std::function<double(const ParameterSet&)>;

  DirichletTerm(std::string name, const ParameterSet& params) : name_(std::move(name)), params_(&params) {}

  // Constrain global unknown `dof` to g(parameters). A dof constrained twice is an error.
  void add(int dof, ValueFunction g);
  // Constrain to a constant.
  void add(int dof, double value);

  std::string name() const override { return name_; }
  int num_items() const override { return static_cast<int>(dofs_.size()); }
  int local_size() const override { return 1; }
  bool owns_rows() const override { return true; }
  void item_dofs(int item, int* dofs) const override { dofs[0] = dofs_[item]; }
  Status residual(int item, const double* u, double* r) const override;
  Status jacobian(int item, const double* u, double* r, double* J) const override;
  Status parameter_derivative(int item, int p, const double* u, double* dr) const override;
  // u_i - g_i is linear in u, and g_i affine in the parameters (as dF/dp above takes them): the
  // second and third derivatives are zero.
  bool has_directional_derivative() const override { return true; }
  Status directional_derivative(int, const double*, int, const double* const*, const double* const*,
                                double* r) const override {
    r[0] = 0.0;
    return {};
  }

  const std::vector<int>& dofs() const { return dofs_; }
  double value(int item) const;
  bool constrains(int dof) const;

 private:
  std::string name_;
  const ParameterSet* params_;
  std::vector<int> dofs_;
  std::vector<ValueFunction> values_;
  std::vector<char> constant_;  // value independent of parameters: dF/dp = 0
};

}  // namespace keller
