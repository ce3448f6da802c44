#include "core/Scene.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/SceneText.hpp"

namespace keller {

namespace scene_text {

std::string quote(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string format_value(const SceneValue& v) {
  return std::visit(
      [](const auto& x) -> std::string {
        using X = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<X, double>) {
          std::string s = fmt::format("{}", x);
          if (s.find_first_of(".eEn") == std::string::npos) s += ".0";  // keep it a TOML float
          return s;
        } else if constexpr (std::is_same_v<X, long>) {
          return fmt::format("{}", x);
        } else if constexpr (std::is_same_v<X, bool>) {
          return x ? "true" : "false";
        } else if constexpr (std::is_same_v<X, std::string>) {
          return quote(x);
        } else {
          std::string s = "[";
          for (size_t i = 0; i < x.size(); ++i) s += (i ? ", " : "") + format_value(SceneValue(x[i]));
          return s + "]";
        }
      },
      v);
}

}  // namespace scene_text

namespace scene_text {

std::vector<std::string> split_path(const std::string& path) {
  std::vector<std::string> parts;
  size_t start = 0;
  while (true) {
    const size_t dot = path.find('.', start);
    parts.push_back(path.substr(start, dot == std::string::npos ? std::string::npos : dot - start));
    if (dot == std::string::npos) return parts;
    start = dot + 1;
  }
}

bool bare_key(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
  });
}

// Whether `path` is `pattern` with its "*" segment replaced by a member's name; the name, or "".
std::string member_in(const std::string& pattern, const std::string& path) {
  const std::vector<std::string> a = split_path(pattern), b = split_path(path);
  if (a.size() != b.size()) return "";
  std::string name;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i] == "*") {
      if (!bare_key(b[i])) return "";
      name = b[i];
    } else if (a[i] != b[i]) {
      return "";
    }
  }
  return name;
}

// The family of a template path: what comes before its "*" ("boundaries" of "boundaries.*.type").
std::string family_of(const std::string& pattern) { return pattern.substr(0, pattern.find(".*")); }

}  // namespace scene_text

using scene_text::format_value;
using scene_text::member_in;

// ---------------------------------------------------------------- KeySpec

std::string KeySpec::section() const {
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? std::string() : path.substr(0, dot);
}

std::string KeySpec::key() const {
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? path : path.substr(dot + 1);
}

bool KeySpec::allows_infinity() const {
  const double* d = std::get_if<double>(&default_value);
  return type == Type::Real && d && std::isinf(*d);
}

std::string KeySpec::type_name() const {
  switch (type) {
    case Type::Real: return "a number";
    case Type::Integer: return "an integer";
    case Type::Boolean: return "true or false";
    case Type::String: return "a string";
    case Type::RealList: return "a list of numbers";
  }
  return "?";
}

// ---------------------------------------------------------------- SceneSchema

void SceneSchema::section(const std::string& name, const std::string& doc) {
  for (const auto& s : sections_)
    if (s.first == name) return;
  sections_.emplace_back(name, doc);
}

void SceneSchema::add(KeySpec spec) {
  if (find(spec.path)) throw std::logic_error("scene key '" + spec.path + "' declared twice");
  if (spec.section().empty()) throw std::logic_error("scene key '" + spec.path + "' must be inside a section");
  if (!has_section(spec.section())) section(spec.section(), "");
  keys_.push_back(std::move(spec));
}

void SceneSchema::set_default(const std::string& path, const std::string& value, const std::string& why) {
  auto it = std::find_if(keys_.begin(), keys_.end(), [&](const KeySpec& k) { return k.path == path; });
  if (it == keys_.end() || it->type != KeySpec::Type::String)
    throw std::logic_error("set_default: '" + path + "' is not a declared string key");
  if (!it->choices.empty() && std::find(it->choices.begin(), it->choices.end(), value) == it->choices.end())
    throw std::logic_error("set_default: '" + value + "' is not a choice of '" + path + "'");
  it->default_value = value;
  it->doc += " (this problem's default: " + why + ")";
}

void SceneSchema::real(const std::string& path, double def, const std::string& doc, Range range) {
  add({path, KeySpec::Type::Real, def, doc, range, {}});
}
void SceneSchema::integer(const std::string& path, long def, const std::string& doc, Range range) {
  // every integer key is read as an int: its range stops at int's, so no value is ever narrowed
  range.lo = std::max(range.lo, static_cast<double>(std::numeric_limits<int>::min()));
  range.hi = std::min(range.hi, static_cast<double>(std::numeric_limits<int>::max()));
  if (!range.contains(static_cast<double>(def)))
    throw std::logic_error("scene key '" + path + "': default outside its range");
  add({path, KeySpec::Type::Integer, def, doc, range, {}});
}
void SceneSchema::boolean(const std::string& path, bool def, const std::string& doc) {
  add({path, KeySpec::Type::Boolean, def, doc, {}, {}});
}
void SceneSchema::string(const std::string& path, const std::string& def, const std::string& doc,
                         std::vector<std::string> choices) {
  add({path, KeySpec::Type::String, def, doc, {}, std::move(choices)});
}
void SceneSchema::file_path(const std::string& path, const std::string& doc) {
  KeySpec k{path, KeySpec::Type::String, std::string(), doc, {}, {}};
  k.is_path = true;
  add(std::move(k));
}
void SceneSchema::real_list(const std::string& path, std::vector<double> def, const std::string& doc, Range range) {
  add({path, KeySpec::Type::RealList, std::move(def), doc, range, {}});
}

const KeySpec* SceneSchema::find(const std::string& path) const {
  for (const auto& k : keys_)
    if (k.path == path) return &k;
  return nullptr;
}

const KeySpec* SceneSchema::template_of(const std::string& path) const {
  for (const auto& k : keys_)
    if (k.is_template() && !member_in(k.path, path).empty()) return &k;
  return nullptr;
}

bool SceneSchema::has_section(const std::string& name) const {
  return std::any_of(sections_.begin(), sections_.end(), [&](const auto& s) { return s.first == name; });
}

std::vector<std::string> SceneSchema::keys_in(const std::string& section) const {
  std::vector<std::string> out;
  for (const auto& k : keys_)
    if (k.section() == section) out.push_back(k.key());
  return out;
}

std::string SceneSchema::help() const {
  std::string out;
  for (const auto& [name, doc] : sections_) {
    out += fmt::format("[{}]{}\n", name, doc.empty() ? "" : "  # " + doc);
    for (const auto& k : keys_) {
      if (k.section() != name) continue;
      std::string allowed;
      if (k.type == KeySpec::Type::String && !k.choices.empty()) {
        allowed = "one of:";
        for (const auto& c : k.choices) allowed += " " + c;
      } else if (k.type == KeySpec::Type::Real || k.type == KeySpec::Type::Integer ||
                 k.type == KeySpec::Type::RealList) {
        if (k.range.describe() != "any number") allowed = k.range.describe();
      }
      out += fmt::format("  {} = {}\n      {}; {}{}\n", k.key(), format_value(k.default_value), k.doc, k.type_name(),
                         allowed.empty() ? "" : ", " + allowed);
    }
    out += "\n";
  }
  return out;
}

}  // namespace keller
