#include "core/ParameterSet.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace keller {

int ParameterSet::add(std::string name, double value, std::string doc, double lower, double upper) {
  return add(std::move(name), value, std::move(doc), Range::between(lower, upper));
}

int ParameterSet::add(std::string name, double value, std::string doc, const Range& range) {
  if (has(name)) throw std::invalid_argument("parameter '" + name + "' declared twice");
  if (!range.contains(value))
    throw std::out_of_range(
        fmt::format("parameter '{}' = {} outside its range: must be {}", name, value, range.describe()));
  params_.push_back({std::move(name), value, range.lo, range.hi, std::move(doc), range.lo_open, range.hi_open});
  values_.push_back(value);
  ++version_;
  return size() - 1;
}

bool ParameterSet::has(const std::string& name) const {
  for (const auto& p : params_)
    if (p.name == name) return true;
  return false;
}

int ParameterSet::index(const std::string& name) const {
  for (int i = 0; i < size(); ++i)
    if (params_[i].name == name) return i;
  throw std::invalid_argument("unknown parameter '" + name + "'; this problem has: " + names());
}

void ParameterSet::set(int i, double v) {
  const Parameter& p = params_.at(static_cast<size_t>(i));
  if (!p.range().contains(v)) {
    // (a parameter fixed at one value says why)
    const bool fixed = p.range().lo == p.range().hi;
    throw std::out_of_range(fmt::format("parameter '{}' = {} outside its range: must be {}{}", p.name, v,
                                        p.range().describe(), fixed ? " (" + p.doc + ")" : ""));
  }
  values_[i] = v;
  params_[i].value = v;
  ++version_;
}

std::string ParameterSet::names() const {
  std::string s;
  for (const auto& p : params_) s += (s.empty() ? "" : ", ") + p.name;
  return s;
}

}  // namespace keller
