#include "core/Quantities.hpp"

#include <algorithm>
#include <stdexcept>

namespace keller {

void Quantities::add(std::string name, Function f) {
  if (has(name)) throw std::invalid_argument("quantity '" + name + "' is declared twice");
  names_.push_back(std::move(name));
  functions_.push_back(std::move(f));
}

bool Quantities::has(const std::string& name) const {
  return std::find(names_.begin(), names_.end(), name) != names_.end();
}

double Quantities::value(const std::string& name, const Vector& u) const {
  const auto it = std::find(names_.begin(), names_.end(), name);
  if (it == names_.end()) throw std::invalid_argument("no quantity named '" + name + "'");
  return functions_[static_cast<size_t>(it - names_.begin())](u);
}

void Quantities::evaluate(const Vector& u, std::vector<double>& values) const {
  values.resize(functions_.size());
  for (size_t k = 0; k < functions_.size(); ++k) values[k] = functions_[k](u);
}

}  // namespace keller
