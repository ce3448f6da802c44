#include "core/Scene.hpp"

#include <fmt/format.h>

#include <toml++/toml.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/SceneText.hpp"

namespace keller {

using scene_text::family_of;
using scene_text::format_value;
using scene_text::member_in;
using scene_text::quote;

// ---------------------------------------------------------------- Scene

namespace {

struct Leaf {
  std::string path;
  const toml::node* node;
  int line;
};

void flatten(const toml::table& t, const std::string& prefix, std::vector<Leaf>& out,
             std::vector<std::pair<std::string, int>>& tables) {
  for (auto&& [k, v] : t) {
    const std::string path = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    // keys set by --set overrides come from a document named "override": line 0
    const bool overridden = v.source().path && *v.source().path == "override";
    const int line = overridden ? 0 : static_cast<int>(v.source().begin.line);
    if (const toml::table* sub = v.as_table()) {
      tables.emplace_back(path, line);
      flatten(*sub, path, out, tables);
    } else {
      out.push_back({path, &v, line});
    }
  }
}

std::string node_kind(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a number";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::array: return "a list";
    case toml::node_type::table: return "a table";
    default: return "a date/time";
  }
}

std::string node_text(const toml::node& n) {
  if (const auto s = n.value<std::string>()) return quote(s->size() > 40 ? s->substr(0, 37) + "..." : *s);
  std::ostringstream os;
  n.visit([&](auto&& x) { os << x; });
  std::string s = os.str();
  if (s.size() > 40) s = s.substr(0, 37) + "...";
  return s;
}

// A path from a scene file (line > 0) relative to the file's folder, from an override (line 0)
// relative to the working directory; absolute and normalised either way. A source that is not a
// file (a scene stored in an output) holds absolute paths already.
std::string absolute_path(const std::string& value, const std::string& source, int line) {
  namespace fs = std::filesystem;
  if (value.empty() || fs::path(value).is_absolute()) return value;
  std::error_code ec;
  const fs::path base = line > 0 && fs::is_regular_file(source, ec) ? fs::absolute(fs::path(source), ec).parent_path()
                                                                    : fs::current_path(ec);
  return (base / value).lexically_normal().string();
}

std::string location(const std::string& source, int line) {
  return line > 0 ? fmt::format("{}:{}", source, line) : fmt::format("{} (--set)", source);
}

toml::table parse_toml(const std::string& text, const std::string& source) {
  try {
    return toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    throw SceneError(fmt::format("{}:{}:{}: not valid TOML: {}", source, e.source().begin.line, e.source().begin.column,
                                 e.description()));
  }
}

std::string read_file(const std::string& file) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(file, ec)) throw SceneError(fmt::format("scene file '{}' does not exist", file));
  if (fs::is_directory(file, ec)) throw SceneError(fmt::format("scene file '{}' is a directory", file));
  std::ifstream in(file, std::ios::binary);
  if (!in) throw SceneError(fmt::format("scene file '{}' cannot be read", file));
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

std::string Scene::peek_string(const std::string& file, const std::string& path, const std::string& fallback) {
  return peek_string_in(read_file(file), file, path, fallback);
}

std::string Scene::peek_string_in(const std::string& text, const std::string& file, const std::string& path,
                                  const std::string& fallback) {
  const toml::table t = parse_toml(text, file);
  const toml::node_view<const toml::node> v = t.at_path(path);
  if (!v) return fallback;
  if (const auto s = v.value<std::string>()) return *s;
  throw SceneError(fmt::format("{}:{}: key '{}' must be a string, got {}", file, v.node()->source().begin.line, path,
                               node_kind(*v.node())));
}

Scene Scene::load(const std::string& file, const SceneSchema& schema, const std::vector<std::string>& overrides) {
  return parse(read_file(file), file, schema, overrides);
}

Scene Scene::parse(const std::string& text, const std::string& source, const SceneSchema& schema,
                   const std::vector<std::string>& overrides) {
  Scene scene;
  scene.schema_ = schema;
  scene.source_ = source;
  toml::table t = parse_toml(text, source);
  // overrides: parse each as a one-key TOML document and insert it at its path
  std::vector<toml::table> override_docs;
  for (const std::string& o : overrides) {
    const auto eq = o.find('=');
    if (eq == std::string::npos || eq == 0)
      throw SceneError(fmt::format("override '{}' is not of the form section.key=value", o));
    const std::string path = o.substr(0, eq), value = o.substr(eq + 1);
    if (value.find_first_of("\n\r") != std::string::npos)
      throw SceneError(fmt::format("override '{}': a value cannot contain a line break", path));
    const auto dot = path.rfind('.');
    if (dot == std::string::npos) throw SceneError(fmt::format("override '{}': the key needs its section", o));
    toml::table doc;
    try {
      doc = toml::parse(std::string_view("v = " + value), std::string_view("override"));
    } catch (const toml::parse_error&) {
      try {  // a bare word is taken as a string: --set mesh.name=M1
        doc = toml::parse(std::string_view("v = \"" + value + "\""), std::string_view("override"));
      } catch (const toml::parse_error& e) {
        throw SceneError(fmt::format("override '{}': not a TOML value: {}", o, e.description()));
      }
    }
    if (doc.size() != 1 || !doc.get("v"))
      throw SceneError(fmt::format("override '{}': the value must be one TOML value", o));
    toml::table* sec = &t;
    const std::string section = path.substr(0, dot);
    size_t start = 0;
    while (start <= section.size()) {
      const size_t end = section.find('.', start);
      const std::string part = section.substr(start, end == std::string::npos ? std::string::npos : end - start);
      auto [it, inserted] = sec->insert(part, toml::table{});
      sec = it->second.as_table();
      if (!sec) throw SceneError(fmt::format("override '{}': '{}' is not a section", o, part));
      if (end == std::string::npos) break;
      start = end + 1;
    }
    sec->insert_or_assign(path.substr(dot + 1), *doc.get("v"));
  }
  std::vector<Leaf> leaves;
  std::vector<std::pair<std::string, int>> tables;
  flatten(t, "", leaves, tables);

  auto section_list = [&]() {
    std::string s;
    for (const auto& [name, doc] : schema.sections()) s += (s.empty() ? "" : ", ") + name;
    return s;
  };
  // tables and keys of a family's members ([boundaries.inlet]) get their concrete keys first
  for (const auto& [path, line] : tables)
    for (const auto& [name, doc] : schema.sections())
      if (name.find('*') != std::string::npos && !member_in(name, path).empty())
        scene.add_member(family_of(name), member_in(name, path));
  for (const Leaf& leaf : leaves)
    if (const KeySpec* k = schema.template_of(leaf.path))
      scene.add_member(family_of(k->path), member_in(k->path, leaf.path));
  for (const auto& [path, line] : tables) {
    if (scene.schema_.has_section(path)) continue;
    bool prefix_of_section = false;
    for (const auto& [name, doc] : schema.sections())
      if (name.rfind(path + ".", 0) == 0) prefix_of_section = true;
    if (!prefix_of_section)
      throw SceneError(
          fmt::format("{}: unknown section [{}]; allowed sections: {}", location(source, line), path, section_list()));
  }
  for (const Leaf& leaf : leaves) {
    const KeySpec* spec = scene.schema_.find(leaf.path);
    if (spec && spec->is_template()) spec = nullptr;  // a member named "*"
    if (!spec) {
      const auto dot = leaf.path.rfind('.');
      const std::string sec = dot == std::string::npos ? "" : leaf.path.substr(0, dot);
      if (sec.empty() || !scene.schema_.has_section(sec))
        throw SceneError(fmt::format("{}: unknown key '{}' outside any known section; allowed sections: {}",
                                     location(source, leaf.line), leaf.path, section_list()));
      std::string allowed;
      for (const auto& k : scene.schema_.keys_in(sec)) allowed += (allowed.empty() ? "" : ", ") + k;
      throw SceneError(fmt::format("{}: unknown key '{}'; keys allowed in [{}]: {}", location(source, leaf.line),
                                   leaf.path, sec, allowed));
    }
    const toml::node& n = *leaf.node;
    auto wrong_type = [&]() {
      return SceneError(fmt::format("{}: key '{}' must be {}, got {} ({})", location(source, leaf.line), leaf.path,
                                    spec->type_name(), node_kind(n), node_text(n)));
    };
    auto out_of_range = [&](double v) {
      return SceneError(fmt::format("{}: key '{}' = {} is out of range: must be {}", location(source, leaf.line),
                                    leaf.path, v, spec->range.describe()));
    };
    auto not_finite = [&](double v) {
      return SceneError(
          fmt::format("{}: key '{}' = {} is not a finite number{}", location(source, leaf.line), leaf.path, v,
                      spec->allows_infinity() ? "" : fmt::format(" (must be {})", spec->range.describe())));
    };
    SceneValue value;
    switch (spec->type) {
      case KeySpec::Type::Real: {
        double v = 0;
        if (n.is_floating_point())
          v = *n.value<double>();
        else if (n.is_integer())
          v = static_cast<double>(*n.value<int64_t>());
        else
          throw wrong_type();
        if (!std::isfinite(v) && !(std::isinf(v) && spec->allows_infinity())) throw not_finite(v);
        if (!spec->range.contains(v)) throw out_of_range(v);
        value = v;
        break;
      }
      case KeySpec::Type::Integer: {
        if (!n.is_integer()) throw wrong_type();
        const long v = static_cast<long>(*n.value<int64_t>());
        if (!spec->range.contains(static_cast<double>(v))) throw out_of_range(static_cast<double>(v));
        value = v;
        break;
      }
      case KeySpec::Type::Boolean: {
        if (!n.is_boolean()) throw wrong_type();
        value = *n.value<bool>();
        break;
      }
      case KeySpec::Type::String: {
        if (!n.is_string()) throw wrong_type();
        const std::string v = *n.value<std::string>();
        if (!spec->choices.empty() && std::find(spec->choices.begin(), spec->choices.end(), v) == spec->choices.end()) {
          std::string allowed;
          for (const auto& c : spec->choices) allowed += (allowed.empty() ? "" : ", ") + c;
          throw SceneError(fmt::format("{}: key '{}' = \"{}\" is not one of: {}", location(source, leaf.line),
                                       leaf.path, v, allowed));
        }
        value = spec->is_path ? absolute_path(v, source, leaf.line) : v;
        break;
      }
      case KeySpec::Type::RealList: {
        const toml::array* arr = n.as_array();
        if (!arr) throw wrong_type();
        std::vector<double> v;
        for (const toml::node& e : *arr) {
          double x = 0;
          if (e.is_floating_point())
            x = *e.value<double>();
          else if (e.is_integer())
            x = static_cast<double>(*e.value<int64_t>());
          else
            throw wrong_type();
          if (!std::isfinite(x)) throw not_finite(x);
          if (!spec->range.contains(x)) throw out_of_range(x);
          v.push_back(x);
        }
        value = std::move(v);
        break;
      }
    }
    scene.values_[leaf.path] = std::move(value);
    scene.lines_[leaf.path] = leaf.line;
  }
  for (const KeySpec& k : scene.schema_.keys())
    if (!k.is_template() && !scene.values_.count(k.path)) scene.values_[k.path] = k.default_value;
  return scene;
}

void Scene::add_member(const std::string& family, const std::string& name) {
  const std::string pattern = family + ".*";
  std::vector<KeySpec> concrete;
  for (const KeySpec& k : schema_.keys())
    if (k.is_template() && k.path.rfind(pattern, 0) == 0) {
      KeySpec c = k;
      c.path = family + "." + name + k.path.substr(pattern.size());
      if (!schema_.find(c.path)) concrete.push_back(std::move(c));
    }
  for (const auto& [section, doc] : schema_.sections())
    if (section == pattern && !schema_.has_section(family + "." + name)) {
      const std::string member_doc = doc;
      schema_.section(family + "." + name, member_doc);
      break;
    }
  for (KeySpec& c : concrete) schema_.add(std::move(c));
}

std::vector<std::string> Scene::members(const std::string& family) const {
  std::vector<std::string> out;
  for (const KeySpec& k : schema_.keys()) {
    if (k.is_template()) continue;
    const KeySpec* t = schema_.template_of(k.path);
    if (!t || family_of(t->path) != family) continue;
    const std::string name = member_in(t->path, k.path);
    if (std::find(out.begin(), out.end(), name) == out.end()) out.push_back(name);
  }
  return out;
}

const SceneValue& Scene::get(const std::string& path, KeySpec::Type type) const {
  const KeySpec* spec = schema_.find(path);
  if (!spec) throw std::logic_error("scene key '" + path + "' read but never declared");
  if (spec->type != type) throw std::logic_error("scene key '" + path + "' read with the wrong type");
  return values_.at(path);
}

double Scene::real(const std::string& path) const { return std::get<double>(get(path, KeySpec::Type::Real)); }
int Scene::integer(const std::string& path) const {
  return static_cast<int>(std::get<long>(get(path, KeySpec::Type::Integer)));  // the range fits int (SceneSchema)
}
bool Scene::boolean(const std::string& path) const { return std::get<bool>(get(path, KeySpec::Type::Boolean)); }
const std::string& Scene::string(const std::string& path) const {
  return std::get<std::string>(get(path, KeySpec::Type::String));
}
const std::vector<double>& Scene::real_list(const std::string& path) const {
  return std::get<std::vector<double>>(get(path, KeySpec::Type::RealList));
}

bool Scene::given(const std::string& path) const { return lines_.count(path) > 0; }

bool Scene::differs_from_default(const std::string& path) const {
  const KeySpec* spec = schema_.find(path);
  if (!spec) throw std::logic_error("scene key '" + path + "' read but never declared");
  return given(path) && !(values_.at(path) == spec->default_value);
}

SceneError Scene::error(const std::string& path, const std::string& what) const {
  auto it = lines_.find(path);
  if (it != lines_.end()) return SceneError(fmt::format("{}: key '{}': {}", location(source_, it->second), path, what));
  return SceneError(fmt::format("{}: key '{}' (default): {}", source_, path, what));
}

std::string Scene::canonical_values(const std::vector<std::string>& keys) const {
  std::string out;
  for (const auto& k : schema_.keys()) {
    if (k.is_template() || (!keys.empty() && std::find(keys.begin(), keys.end(), k.path) == keys.end())) continue;
    out += fmt::format("{} = {}\n", k.path, format_value(values_.at(k.path)));
  }
  return out;
}

std::string Scene::canonical_defaults(const std::vector<std::string>& keys) const {
  std::string out;
  for (const auto& k : schema_.keys()) {
    if (k.is_template() || (!keys.empty() && std::find(keys.begin(), keys.end(), k.path) == keys.end())) continue;
    out += fmt::format("{} = {}\n", k.path, format_value(k.default_value));
  }
  return out;
}

std::string Scene::resolved_toml() const {
  std::string out = fmt::format("# resolved scene from {}\n", source_);
  for (const auto& [name, doc] : schema_.sections()) {
    std::string body;
    for (const auto& k : schema_.keys()) {
      if (k.section() != name || k.is_template()) continue;
      body += fmt::format("{} = {}{}\n", k.key(), format_value(values_.at(k.path)), given(k.path) ? "" : "  # default");
    }
    if (!body.empty()) out += fmt::format("\n[{}]\n{}", name, body);
  }
  return out;
}

std::string Scene::non_default_toml() const {
  std::string out = fmt::format("# scene {}: the keys that differ from their defaults\n", source_);
  for (const auto& [name, doc] : schema_.sections()) {
    std::string body;
    for (const auto& k : schema_.keys())
      if (k.section() == name && !k.is_template() && differs_from_default(k.path))
        body += fmt::format("{} = {}\n", k.key(), format_value(values_.at(k.path)));
    if (!body.empty()) out += fmt::format("\n[{}]\n{}", name, body);
  }
  return out;
}

}  // namespace keller
