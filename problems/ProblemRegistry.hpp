// The registry of problem types a scene can name in [problem] type: each declares its scene
// keys and builds itself from a validated scene. The driver in runs/ reads it; a program that
// links keller adds its own types (register_problem_type) and then runs keller's command line
// (runs/CommandLine.hpp) with them: docs/own_problem.md.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/Problem.hpp"
#include "core/Scene.hpp"

namespace keller {

struct ProblemType {
  std::string name;
  std::string doc;
  std::function<void(SceneSchema&)> declare;
  std::function<std::unique_ptr<Problem>(const Scene&)> build;
  // Solver keys whose best value depends on the problem: {key, value, why}, applied to the
  // schema's defaults so that a scene of this problem gets them without setting them.
  struct Default {
    std::string key, value, why;
  };
  std::vector<Default> defaults = {};
  // A lower estimate of the memory a solve of a scene of this type takes, from its keys alone
  // (nothing is built: a size the machine cannot hold is refused, not run out of memory): so many
  // bytes per element or grid interval, measured as the peak resident memory of keller solve
  // (docs/performance.md), and the key that sets the size. Null: not estimated (small problems).
  struct Memory {
    double bytes = 0;
    std::string key;   // e.g. "mesh.name", "bratu.intervals"
    std::string size;  // e.g. "2400 elements"
  };
  std::function<Memory(const Scene&)> memory = nullptr;
};

// keller's own types, then the registered ones in the order of registration.
const std::vector<ProblemType>& problem_types();
// Adds a type of the calling program, with every command of keller for its scenes. Register
// before any command runs (the references problem_type returns may move). Throws
// std::invalid_argument for a name that is empty, has a character other than a-z, 0-9, '-' and
// '_', or is taken, and for a type without declare or build.
void register_problem_type(ProblemType type);
// Throws std::invalid_argument listing the known types.
const ProblemType& problem_type(const std::string& name);
std::vector<std::string> problem_type_names();

}  // namespace keller
