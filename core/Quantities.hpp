// Named scalars of a solution, each with its own function: a problem declares its observables
// and its monitors by name, evaluates all of them for a branch point, or one alone (a monitor,
// a stop criterion) without computing the others.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/Status.hpp"
#include "core/Types.hpp"

namespace keller {

class Quantities {
 public:
  using Function = std::function<double(const Vector&)>;

  // Declares a quantity; throws std::invalid_argument for a name already declared.
  void add(std::string name, Function f);
  const std::vector<std::string>& names() const { return names_; }
  bool has(const std::string& name) const;
  // One quantity; throws std::invalid_argument for a name not declared.
  double value(const std::string& name, const Vector& u) const;
  // Every quantity in the order of declaration.
  void evaluate(const Vector& u, std::vector<double>& values) const;

 private:
  std::vector<std::string> names_;
  std::vector<Function> functions_;
};

}  // namespace keller
