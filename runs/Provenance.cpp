#include "runs/Provenance.hpp"

#include <fmt/format.h>

#include "core/SparseLU.hpp"

#ifndef KELLER_VERSION
#error "runs/CMakeLists.txt defines KELLER_VERSION, KELLER_COMMIT and KELLER_BUILD_TYPE for this file"
#endif

namespace keller {

namespace {

std::string& recorded_command_line() {
  static std::string line = "unknown";
  return line;
}

// A word as a POSIX shell reads it back: as it is when it holds nothing the shell interprets,
// else in single quotes.
std::string shell_word(const std::string& w) {
  if (!w.empty() && w.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-+=/.,:@%") ==
                        std::string::npos)
    return w;
  std::string out = "'";
  for (char c : w) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

constexpr const char* kGroup = "/provenance";

}  // namespace

Provenance Provenance::current() {
  Provenance p;
  p.version = KELLER_VERSION;
  p.commit = KELLER_COMMIT;
  p.build_type = KELLER_BUILD_TYPE;
  p.linear_solver = to_string(resolved_backend(SparseLUOptions{}));
  p.command_line = recorded_command_line();
  return p;
}

void Provenance::record_command_line(int argc, char** argv) {
  std::string line;
  for (int i = 0; i < argc; ++i) {
    if (i > 0) line += ' ';
    line += shell_word(argv[i]);
  }
  recorded_command_line() = line;
}

std::string Provenance::version_text() const {
  return fmt::format("keller {}\ncommit: {}\nbuild type: {}\nlinear solver: {}{}", version, commit,
                     build_type.empty() ? "none" : build_type, linear_solver,
                     mumps_available() ? " (umfpack too: linear_solver.backend)" : " (built without MUMPS)");
}

void Provenance::write(H5File& file) const {
  file.create_group(kGroup);
  file.set_attribute(kGroup, "keller_version", version);
  file.set_attribute(kGroup, "commit", commit);
  file.set_attribute(kGroup, "build_type", build_type);
  file.set_attribute(kGroup, "linear_solver", linear_solver);
  file.set_attribute(kGroup, "command_line", command_line);
}

std::optional<Provenance> Provenance::read(const H5File& file) {
  if (!file.exists(kGroup)) return std::nullopt;
  Provenance p;
  auto get = [&](const char* name) {
    return file.has_attribute(kGroup, name) ? file.read_string_attribute(kGroup, name) : std::string("unknown");
  };
  p.version = get("keller_version");
  p.commit = get("commit");
  p.build_type = get("build_type");
  p.linear_solver = get("linear_solver");
  p.command_line = get("command_line");
  return p;
}

}  // namespace keller
