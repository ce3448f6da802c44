// Internal to core/Scene*.cpp: how scene values are written as TOML and how a family's member
// paths ("boundaries.inlet.type") are matched against template paths ("boundaries.*.type").
#pragma once

#include <string>

#include "core/Scene.hpp"

namespace keller::scene_text {

// A TOML string literal.
std::string quote(const std::string& s);
// A value as TOML (numbers keep a decimal point, so that they read back as numbers).
std::string format_value(const SceneValue& v);
// The member's name if `path` is `pattern` with its "*" segment replaced by a bare TOML key, else "".
std::string member_in(const std::string& pattern, const std::string& path);
// The family of a template path: what comes before its "*" ("boundaries" of "boundaries.*.type").
std::string family_of(const std::string& pattern);

}  // namespace keller::scene_text
