// Named continuation parameters owned by a problem: value, admissible range and a one-line doc.
// Kernels read values by index through values(); continuation reads and writes them by name.
#pragma once

#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "core/Range.hpp"

namespace keller {

struct Parameter {
  std::string name;
  double value = 0.0;
  double lower = -std::numeric_limits<double>::infinity();  // admissible range (inclusive unless open)
  double upper = std::numeric_limits<double>::infinity();
  std::string doc;
  bool lower_open = false, upper_open = false;
  Range range() const { return {lower, upper, lower_open, upper_open}; }
};

class ParameterSet {
 public:
  // Adds a parameter and returns its index; throws if the name exists or the value is out of range.
  int add(std::string name, double value, std::string doc, double lower = -std::numeric_limits<double>::infinity(),
          double upper = std::numeric_limits<double>::infinity());
  // The same with a range that may have open ends (Wi > 0).
  int add(std::string name, double value, std::string doc, const Range& range);
  int size() const { return static_cast<int>(params_.size()); }
  bool has(const std::string& name) const;
  // Index of a named parameter; throws std::invalid_argument listing the known names.
  int index(const std::string& name) const;
  double get(const std::string& name) const { return params_[index(name)].value; }
  double value(int i) const { return values_[i]; }
  // Sets a value; throws std::out_of_range naming the parameter and its range if outside it.
  void set(const std::string& name, double v) { set(index(name), v); }
  void set(int i, double v);
  bool admissible(int i, double v) const { return params_[i].range().contains(v); }
  // The points {v - h, v + h} of a central difference in parameter i at its value v, each moved
  // back to v where it would leave the admissible range: one-sided at a bound or within h of it,
  // and an open bound (Gamma > 0) is never evaluated.
  std::pair<double, double> difference_points(int i, double h) const {
    const double v = values_[i];
    return {admissible(i, v - h) ? v - h : v, admissible(i, v + h) ? v + h : v};
  }
  const Parameter& info(int i) const { return params_[i]; }
  const std::vector<Parameter>& list() const { return params_; }
  const double* values() const { return values_.data(); }
  // Incremented by every set(); lets a problem refresh what depends on parameters.
  unsigned long version() const { return version_; }
  std::string names() const;  // "Re, Gamma, beta"

 private:
  std::vector<Parameter> params_;
  std::vector<double> values_;
  unsigned long version_ = 0;
};

}  // namespace keller
