// Scene files: TOML, validated against a schema before anything runs. Every key is declared by
// the code that consumes it (type, default, admissible range or choices, one-line doc); unknown
// keys, wrong types and out-of-range values are SceneErrors naming the file, the line, the key
// and what is allowed. The resolved scene (every key, explicit or default) is printable as TOML
// and stored with every output.
#pragma once

#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "core/Range.hpp"

namespace keller {

class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

using SceneValue = std::variant<double, long, bool, std::string, std::vector<double>>;

struct KeySpec {
  enum class Type { Real, Integer, Boolean, String, RealList };
  std::string path;  // "section.key" (sections may nest: "a.b.key")
  Type type = Type::Real;
  SceneValue default_value;
  std::string doc;
  Range range;                       // Real, Integer, RealList entries
  std::vector<std::string> choices;  // String: allowed values (empty = any)
  // String: a file's path. A relative path in a scene file is relative to the file's folder and is
  // stored absolute (so that a scene stored in an output, read back anywhere, names the same
  // file); one given by an override (--set) is relative to the working directory.
  bool is_path = false;
  std::string section() const;    // "mesh" for "mesh.nx"
  std::string key() const;        // "nx"
  std::string type_name() const;  // "a number", "an integer", ...
  // Numbers must be finite, except in a Real key whose default is infinite (meaning "none",
  // as for a bound): it also takes inf or -inf. NaN is never a value.
  bool allows_infinity() const;
  // A template key of a family of tables the scene names freely: a path with "*" for the member's
  // name, as "boundaries.*.type" ([boundaries.inlet] type = ...) or "mesh.geo_parameters.*" (any
  // number of named numbers). A scene's members get concrete keys made from their templates.
  bool is_template() const { return path.find('*') != std::string::npos; }
};

class SceneSchema {
 public:
  // Declare a section (a TOML table) with a one-line doc; keys are added with full paths.
  void section(const std::string& name, const std::string& doc);
  void real(const std::string& path, double def, const std::string& doc, Range range = Range::any());
  // Integer keys are read as int: their range is clipped to int's, so a value is range-checked
  // before it is ever narrowed.
  void integer(const std::string& path, long def, const std::string& doc, Range range = Range::any());
  void boolean(const std::string& path, bool def, const std::string& doc);
  void string(const std::string& path, const std::string& def, const std::string& doc,
              std::vector<std::string> choices = {});
  void real_list(const std::string& path, std::vector<double> def, const std::string& doc, Range range = Range::any());
  // A String key holding a file's path (KeySpec::is_path), "" by default.
  void file_path(const std::string& path, const std::string& doc);

  // A different default for a declared string key (a problem type's own choice of a common key,
  // such as its best fill-reducing ordering); the doc says so. Throws std::logic_error for a key
  // that is not declared, not a string, or a value outside its choices.
  void set_default(const std::string& path, const std::string& value, const std::string& why);

  const KeySpec* find(const std::string& path) const;
  // The template key a concrete path is a member of ("boundaries.inlet.type" of "boundaries.*.type"),
  // or null. A member's name is one TOML bare key: letters, digits, '_' and '-'.
  const KeySpec* template_of(const std::string& path) const;
  bool has_section(const std::string& name) const;
  const std::vector<KeySpec>& keys() const { return keys_; }
  const std::vector<std::pair<std::string, std::string>>& sections() const { return sections_; }
  std::vector<std::string> keys_in(const std::string& section) const;
  // Human-readable listing of every section and key: type, default, range, doc.
  std::string help() const;

 private:
  friend class Scene;  // adds the concrete keys of a family's members
  void add(KeySpec spec);
  std::vector<KeySpec> keys_;
  std::vector<std::pair<std::string, std::string>> sections_;
};

class Scene {
 public:
  // Reads and validates a scene file; throws SceneError (missing file, TOML syntax, unknown
  // key or section, wrong type, value out of range).
  // `overrides` are "section.key=value" strings (value in TOML syntax) applied on top of the
  // file and validated like it; errors name them as "override 'mesh.name=M1'".
  static Scene load(const std::string& file, const SceneSchema& schema, const std::vector<std::string>& overrides = {});
  static Scene parse(const std::string& text, const std::string& source, const SceneSchema& schema,
                     const std::vector<std::string>& overrides = {});
  // Reads one string key without validating the rest (to pick the schema, e.g. problem.type);
  // returns `fallback` when absent. Throws SceneError on a missing file or bad TOML.
  static std::string peek_string(const std::string& file, const std::string& path, const std::string& fallback);
  static std::string peek_string_in(const std::string& text, const std::string& source, const std::string& path,
                                    const std::string& fallback);

  double real(const std::string& path) const;
  int integer(const std::string& path) const;
  bool boolean(const std::string& path) const;
  const std::string& string(const std::string& path) const;
  const std::vector<double>& real_list(const std::string& path) const;
  // The names of the members the scene gives a family, in the order of the schema's keys: the
  // tables [boundaries.<name>] for "boundaries", the keys of [mesh.geo_parameters] for
  // "mesh.geo_parameters". Their keys are read with their concrete paths ("boundaries.inlet.type").
  std::vector<std::string> members(const std::string& family) const;
  // Whether the file set this key explicitly (rather than taking the default).
  bool given(const std::string& path) const;
  // Whether the key's value differs from its default (set explicitly to something else). Checks
  // that a key does not apply use this, so that a resolved scene, which lists every key, loads.
  bool differs_from_default(const std::string& path) const;
  // An error about a key, in the same format as validation errors (for cross-key checks).
  SceneError error(const std::string& path, const std::string& what) const;

  const std::string& source() const { return source_; }
  // Every declared key with its resolved value, as TOML, with the docs as comments.
  std::string resolved_toml() const;
  // The keys whose values differ from their defaults, as TOML under a comment naming the source
  // (what a run prints: the resolved scene goes to its file).
  std::string non_default_toml() const;
  // The canonical form of the resolved values of `keys` (all keys when empty): one
  // "section.key = value" line each, in declaration order, no comments. Two scenes that resolve
  // to the same values give the same text, however the files were written.
  std::string canonical_values(const std::vector<std::string>& keys = {}) const;
  // The same lines with every key's default instead of its value.
  std::string canonical_defaults(const std::vector<std::string>& keys = {}) const;
  const SceneSchema& schema() const { return schema_; }

 private:
  const SceneValue& get(const std::string& path, KeySpec::Type type) const;
  // Adds the concrete keys of the member `name` of the family `family` (every template key of the
  // family, with its default) to this scene's schema, once.
  void add_member(const std::string& family, const std::string& name);
  SceneSchema schema_;
  std::string source_;
  std::map<std::string, SceneValue> values_;
  std::map<std::string, int> lines_;  // line of each explicitly given key
};

}  // namespace keller
