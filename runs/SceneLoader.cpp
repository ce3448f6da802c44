#include "runs/SceneLoader.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <fstream>
#include <iterator>

#include "continuation/start/StartSolver.hpp"
#include "core/Newton.hpp"
#include "core/SparseLU.hpp"
#include "runs/OutputFile.hpp"

namespace keller {

void declare_common_keys(SceneSchema& s) {
  s.section("problem", "which problem the scene describes");
  s.string("problem.type", "channel", "problem type", problem_type_names());
  declare_newton_keys(s);
  StartOptions::declare(s);
  declare_linear_solver_keys(s);
  s.section("output", "what is written besides the HDF5 file");
  s.boolean("output.xdmf", true, "write an XDMF file next to the HDF5 file for ParaView");
}

namespace {

const ProblemType& type_named(const std::string& name, const std::string& source) {
  try {
    return problem_type(name);
  } catch (const std::invalid_argument& e) {
    throw SceneError(fmt::format("{}: key 'problem.type': {}", source, e.what()));
  }
}

LoadedScene loaded(const ProblemType& type, const std::function<void(SceneSchema&)>& extra,
                   const std::function<Scene(const SceneSchema&)>& load) {
  SceneSchema schema;
  declare_common_keys(schema);
  type.declare(schema);
  for (const ProblemType::Default& d : type.defaults) schema.set_default(d.key, d.value, d.why);
  if (extra) extra(schema);
  SceneSchema own;
  type.declare(own);
  Scene scene = load(schema);
  // the type's own keys, and the members the scene gives the type's families ([boundaries.inlet])
  std::vector<std::string> physics;
  for (const KeySpec& k : scene.schema().keys()) {
    if (k.is_template() || k.section() == "parameters") continue;
    const KeySpec* t = schema.template_of(k.path);
    if (own.find(k.path) || (t && own.find(t->path))) physics.push_back(k.path);
  }
  return {std::move(scene), &type, std::move(physics)};
}

// problem.type as the overrides leave it
std::string overridden_type(std::string type_name, const std::vector<std::string>& overrides) {
  for (const std::string& o : overrides)
    if (o.rfind("problem.type=", 0) == 0) {
      type_name = o.substr(13);
      if (type_name.size() >= 2 && type_name.front() == '"' && type_name.back() == '"')
        type_name = type_name.substr(1, type_name.size() - 2);
    }
  return type_name;
}

// The memory this process may use, in bytes: the machine's physical memory, or the limit of its
// control group (cgroup v2, a container or a batch job) where that is lower; 0 where neither can be told.
double usable_memory() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  double bytes = pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 0.0;
  std::ifstream limit("/sys/fs/cgroup/memory.max");
  double cap = 0;
  if (limit >> cap && cap > 0 && (bytes == 0 || cap < bytes)) bytes = cap;  // ("max": no limit, not read)
  return bytes;
}

}  // namespace

void check_memory(const LoadedScene& loaded) {
  const Scene& scene = loaded.scene;
  if (!loaded.type || !loaded.type->memory) return;
  const ProblemType::Memory m = loaded.type->memory(scene);
  const double have = usable_memory();
  if (have > 0 && m.bytes > have)
    throw scene.error(m.key, fmt::format("the scene needs at least {:.3g} GB of memory to solve ({}), more than this "
                                         "machine's {:.3g} GB usable: choose a smaller size",
                                         m.bytes / 1e9, m.size, have / 1e9));
}

LoadedScene load_scene(const std::string& file, const std::function<void(SceneSchema&)>& extra,
                       const std::vector<std::string>& overrides) {
  const std::string type_name = overridden_type(Scene::peek_string(file, "problem.type", "channel"), overrides);
  return loaded(type_named(type_name, file), extra,
                [&](const SceneSchema& schema) { return Scene::load(file, schema, overrides); });
}

LoadedScene load_scene_text(const std::string& text, const std::string& source,
                            const std::function<void(SceneSchema&)>& extra, const std::vector<std::string>& overrides) {
  const std::string type_name =
      overridden_type(Scene::peek_string_in(text, source, "problem.type", "channel"), overrides);
  return loaded(type_named(type_name, source), extra,
                [&](const SceneSchema& schema) { return Scene::parse(text, source, schema, overrides); });
}

std::unique_ptr<Problem> build_problem(const LoadedScene& loaded, const std::string& file) {
  try {
    return loaded.type->build(loaded.scene);
  } catch (const SceneError&) {
    throw;
  } catch (const std::exception& e) {
    throw SceneError(fmt::format("{}: {}", file, e.what()));
  }
}

std::string scene_help(const std::function<void(SceneSchema&)>& extra) {
  std::string out = "Keys common to every scene:\n\n";
  SceneSchema common;
  declare_common_keys(common);
  if (extra) extra(common);
  out += common.help();
  for (const ProblemType& t : problem_types()) {
    SceneSchema s;
    t.declare(s);
    out += fmt::format("Keys of problem type '{}' ({}):\n\n{}", t.name, t.doc, s.help());
    for (const ProblemType::Default& d : t.defaults)
      out += fmt::format("  {} defaults to \"{}\" for this problem: {}\n\n", d.key, d.value, d.why);
  }
  return out;
}

std::string LoadedScene::physics() const {
  std::string out = scene.canonical_values(physics_keys);
  for (const std::string& key : physics_keys) {
    const KeySpec* spec = scene.schema().find(key);
    if (spec == nullptr || !spec->is_path || scene.string(key).empty()) continue;
    std::ifstream in(scene.string(key), std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    out += fmt::format("{}:content = {}\n", key, in.bad() || !in.is_open() ? "unreadable" : text_hash(bytes));
  }
  return out;
}

std::string scene_summary(const LoadedScene& loaded, const std::string& out) {
  return fmt::format("{}# every key, with its default: keller info {} --scene\n", loaded.scene.non_default_toml(), out);
}

}  // namespace keller
