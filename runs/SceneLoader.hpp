// Assembles the full scene schema for a run (the chosen problem type's keys plus the keys of
// every algorithm the command uses) and loads a scene file against it.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/Scene.hpp"
#include "problems/ProblemRegistry.hpp"

namespace keller {

// Declares the keys every run has: [problem], [newton], [start], [linear_solver], [output].
void declare_common_keys(SceneSchema& schema);

struct LoadedScene {
  Scene scene;
  const ProblemType* type = nullptr;
  // The keys that define the problem's physics and discretisation (the problem type's keys,
  // parameter values excepted): a stored solution is a solution of this scene's problem only
  // if they are equal.
  std::vector<std::string> physics_keys;
  // physics_keys with their values (Scene::canonical_values), as stored in every output file,
  // and for each file a path key names (a mesh's .msh or .geo) a line "KEY:content = HASH" with a
  // hash of the file's bytes: a file changed under the same name is other physics, so a rerun or a
  // restart does not continue a branch made from its old content ("unreadable" where it cannot be
  // read; a .geo's included files are not hashed).
  std::string physics() const;
  // The defaults of every key, in the same form (records_agree: keys added since a file was written).
  std::string defaults() const { return scene.canonical_defaults(); }
};

// Reads problem.type, builds the schema (common keys, the type's keys, and `extra` for the
// command's own sections) and validates the file with the overrides ("section.key=value")
// applied. Throws SceneError.
LoadedScene load_scene(const std::string& file, const std::function<void(SceneSchema&)>& extra = {},
                       const std::vector<std::string>& overrides = {});

// The same for a scene held in memory (the scene stored in an output file, a study's base scene
// read once for all its tasks); `source` names it in messages.
LoadedScene load_scene_text(const std::string& text, const std::string& source,
                            const std::function<void(SceneSchema&)>& extra = {},
                            const std::vector<std::string>& overrides = {});

// Refuses (SceneError naming the key that sets the size) a scene whose lower memory estimate
// (ProblemType::memory) exceeds the memory this process may use (the machine's, or its control
// group's limit): called by the commands that solve, before anything is built.
void check_memory(const LoadedScene& loaded);

// Builds the scene's problem. Throws SceneError: the scene's own errors as they are, a problem's
// refusal of its options (std::exception) prefixed with the scene file `file`.
std::unique_ptr<Problem> build_problem(const LoadedScene& loaded, const std::string& file);

// What a run prints of its scene before it starts: the keys that differ from their defaults, and
// where every key is (/scene of `out`, which `keller info OUT --scene` prints).
std::string scene_summary(const LoadedScene& loaded, const std::string& out);

// The full listing of every key of every problem type, for --help-scene.
std::string scene_help(const std::function<void(SceneSchema&)>& extra = {});

}  // namespace keller
