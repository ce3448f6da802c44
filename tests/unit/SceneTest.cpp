// Scenes: validation errors name the file, line, key and what is allowed; defaults fill in;
// the resolved scene parses back to the same values.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "continuation/engine/ContinuationOptions.hpp"
#include "core/BlockMeshBuilder.hpp"
#include "core/GmshMesh.hpp"
#include "core/Scene.hpp"
#include "problems/cylinder/CylinderProblem.hpp"
#include "runs/SceneLoader.hpp"
#include "runs/TraceCommand.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
namespace fs = std::filesystem;

namespace {

SceneSchema schema() {
  SceneSchema s;
  s.section("mesh", "mesh");
  s.integer("mesh.n", 4, "elements", Range::at_least(1));
  s.real("mesh.length", 7.0, "a length", Range::positive());
  s.string("mesh.kind", "uniform", "kind", {"uniform", "graded"});
  s.boolean("mesh.flag", false, "a flag");
  s.real_list("mesh.stops", {0.5}, "stops", Range::non_negative());
  return s;
}

std::string error_of(const std::string& text) {
  try {
    Scene::parse(text, "s.toml", schema());
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Scene, DefaultsAndValues) {
  const Scene s = Scene::parse("[mesh]\nn = 8\nlength = 3\nstops = [1, 2.5]\n", "s.toml", schema());
  EXPECT_EQ(s.integer("mesh.n"), 8);
  EXPECT_DOUBLE_EQ(s.real("mesh.length"), 3.0);  // an integer is accepted as a number
  EXPECT_EQ(s.string("mesh.kind"), "uniform");
  EXPECT_FALSE(s.boolean("mesh.flag"));
  EXPECT_EQ(s.real_list("mesh.stops"), (std::vector<double>{1.0, 2.5}));
  EXPECT_TRUE(s.given("mesh.n"));
  EXPECT_FALSE(s.given("mesh.kind"));
}

TEST(Scene, ResolvedSceneParsesBackToTheSameValues) {
  const Scene s = Scene::parse("[mesh]\nn = 8\nlength = 1e-3\nkind = \"graded\"\n", "s.toml", schema());
  const Scene t = Scene::parse(s.resolved_toml(), "resolved", schema());
  EXPECT_EQ(t.integer("mesh.n"), 8);
  EXPECT_DOUBLE_EQ(t.real("mesh.length"), 1e-3);
  EXPECT_EQ(t.string("mesh.kind"), "graded");
  EXPECT_EQ(t.real_list("mesh.stops"), (std::vector<double>{0.5}));
}

// What a run prints of its scene: the keys whose values differ from their defaults (a key given
// at its default left out), the same for the resolved scene that lists every key.
TEST(Scene, NonDefaultTomlHoldsTheKeysThatDifferFromTheirDefaults) {
  const Scene s = Scene::parse("[mesh]\nn = 4\nlength = 3\nkind = \"uniform\"\nstops = [0.5, 1]\n", "s.toml", schema());
  EXPECT_EQ(s.non_default_toml(),
            "# scene s.toml: the keys that differ from their defaults\n\n[mesh]\nlength = 3.0\nstops = [0.5, 1.0]\n");
  const Scene t = Scene::parse(s.resolved_toml(), "s.toml", schema());
  EXPECT_EQ(t.non_default_toml(), s.non_default_toml());
  EXPECT_EQ(Scene::parse("", "e.toml", schema()).non_default_toml(),
            "# scene e.toml: the keys that differ from their defaults\n");
}

TEST(Scene, EachKindOfErrorHasItsOwnMessage) {
  EXPECT_EQ(error_of("[mesh]\nnn = 3\n"),
            "s.toml:2: unknown key 'mesh.nn'; keys allowed in [mesh]: n, length, kind, flag, stops");
  EXPECT_EQ(error_of("[mesh]\nn = \"ten\"\n"), "s.toml:2: key 'mesh.n' must be an integer, got a string (\"ten\")");
  EXPECT_EQ(error_of("[mesh]\nn = 2.5\n"), "s.toml:2: key 'mesh.n' must be an integer, got a number (2.5)");
  EXPECT_EQ(error_of("[mesh]\n\nlength = -7\n"), "s.toml:3: key 'mesh.length' = -7 is out of range: must be > 0");
  EXPECT_EQ(error_of("[mesh]\nkind = \"curved\"\n"),
            "s.toml:2: key 'mesh.kind' = \"curved\" is not one of: uniform, graded");
  EXPECT_EQ(error_of("[meshes]\nn = 3\n"), "s.toml:1: unknown section [meshes]; allowed sections: mesh");
  EXPECT_EQ(error_of("n = 3\n"), "s.toml:1: unknown key 'n' outside any known section; allowed sections: mesh");
  EXPECT_EQ(error_of("[mesh]\nstops = [1, -1]\n"), "s.toml:2: key 'mesh.stops' = -1 is out of range: must be >= 0");
  const std::string syntax = error_of("[mesh\nn = 3\n");
  EXPECT_EQ(syntax.rfind("s.toml:1:", 0), 0u) << syntax;
  EXPECT_NE(syntax.find("not valid TOML"), std::string::npos) << syntax;
  EXPECT_THROW(Scene::load("/nonexistent/scene.toml", schema()), SceneError);
}

TEST(Scene, FullChannelSchemaValidatesTheShippedScene) {
  const LoadedScene l = load_scene(test::source_path("runs/scenes/channel_stokes.toml"));
  EXPECT_EQ(l.type->name, "channel");
  EXPECT_EQ(l.scene.string("mesh.name"), "M2");
  EXPECT_DOUBLE_EQ(l.scene.real("parameters.Gamma"), 4.95e-4);
  const std::string help = scene_help();
  EXPECT_NE(help.find("upstream_length = 7.0"), std::string::npos);
  EXPECT_NE(help.find("Lu, length of the rigid channel upstream"), std::string::npos);
}

// A resolved scene (as stored in every output file) loads again and resolves to itself: that is
// how keller export and --restart rebuild a problem from a file.
TEST(Scene, ResolvedScenesOfShippedScenesReload) {
  for (const char* s : {"runs/scenes/channel_stokes.toml", "runs/scenes/cylinder_oldroyd_b.toml",
                        "runs/scenes/bratu2d_fold.toml", "runs/scenes/flow_contraction_oldroyd_b.toml"}) {
    SCOPED_TRACE(s);
    const LoadedScene a = load_scene(test::source_path(s), declare_trace_keys);
    const std::string path = test::scratch_dir("resolved") + "/resolved.toml";
    std::ofstream(path) << a.scene.resolved_toml();
    const LoadedScene b = load_scene(path, declare_trace_keys);
    EXPECT_NO_THROW(a.type->build(b.scene));
    // the same values: only the first line (the source) and the "# default" marks differ
    auto values = [](std::string r) {
      r = r.substr(r.find('\n'));
      for (size_t p; (p = r.find("  # default")) != std::string::npos;) r.erase(p, 11);
      return r;
    };
    EXPECT_EQ(values(a.scene.resolved_toml()), values(b.scene.resolved_toml()));
  }
}

// A problem type's own default for a common solver key: a scene of that problem gets it
// without setting it, a scene that sets the key keeps its value, other problems keep the
// common default, and a bad default is a programming error.
TEST(Scene, AProblemTypesDefaultsApplyToItsScenesOnly) {
  const auto ordering = [](const std::string& text) {
    return load_scene_text(text, "s.toml", declare_trace_keys).scene.string("linear_solver.ordering");
  };
  EXPECT_EQ(ordering("[problem]\ntype = \"collapsible-channel\"\n"), "best");
  EXPECT_EQ(ordering("[problem]\ntype = \"cylinder\"\n"), "best");
  EXPECT_EQ(ordering("[problem]\ntype = \"collapsible-channel\"\n[linear_solver]\nordering = \"amd\"\n"), "amd");
  EXPECT_EQ(ordering("[problem]\ntype = \"channel\"\n"), "amd");
  SceneSchema s = schema();
  s.set_default("mesh.kind", "graded", "a reason");
  EXPECT_EQ(std::get<std::string>(s.find("mesh.kind")->default_value), "graded");
  EXPECT_NE(s.find("mesh.kind")->doc.find("a reason"), std::string::npos);
  EXPECT_THROW(s.set_default("mesh.kind", "curved", "not a choice"), std::logic_error);
  EXPECT_THROW(s.set_default("mesh.n", "3", "not a string key"), std::logic_error);
  EXPECT_THROW(s.set_default("mesh.nope", "x", "not declared"), std::logic_error);
}

namespace {
std::string override_error(const std::string& o) {
  SceneSchema s = schema();
  s.real("mesh.bound", INFINITY, "a bound (inf: none)");
  try {
    Scene::parse("[mesh]\n", "s.toml", s, {o});
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

// Every number is finite unless its key says otherwise (a key whose default is infinite, such as
// a bound, takes inf and -inf); NaN never.
TEST(Scene, NumbersAreFiniteUnlessTheKeyTakesInfinity) {
  EXPECT_EQ(override_error("mesh.length=inf"),
            "s.toml (--set): key 'mesh.length' = inf is not a finite number (must be > 0)");
  EXPECT_EQ(override_error("mesh.length=nan"),
            "s.toml (--set): key 'mesh.length' = nan is not a finite number (must be > 0)");
  EXPECT_EQ(override_error("mesh.stops=[1.0, inf]"),
            "s.toml (--set): key 'mesh.stops' = inf is not a finite number (must be >= 0)");
  EXPECT_EQ(override_error("mesh.bound=inf"), "");
  EXPECT_EQ(override_error("mesh.bound=-inf"), "");
  EXPECT_EQ(override_error("mesh.bound=nan"), "s.toml (--set): key 'mesh.bound' = nan is not a finite number");
  EXPECT_EQ(error_of("[mesh]\nlength = -inf\n"),
            "s.toml:2: key 'mesh.length' = -inf is not a finite number (must be > 0)");
}

// An integer key is read as an int: a value beyond int's range is an out-of-range error before
// anything narrows it.
TEST(Scene, IntegersAreRangeCheckedBeforeNarrowing) {
  EXPECT_EQ(error_of("[mesh]\nn = 2147483658\n"),
            "s.toml:2: key 'mesh.n' = 2147483658 is out of range: must be in [1, 2147483647]");
  EXPECT_EQ(error_of("[mesh]\nn = 2147483647\n"), "");
  EXPECT_EQ(Scene::parse("[mesh]\nn = 2147483647\n", "s.toml", schema()).integer("mesh.n"), 2147483647);
  SceneSchema s;
  EXPECT_THROW(s.integer("a.n", 3000000000L, "a default beyond int"), std::logic_error);
}

TEST(Scene, AnOverrideIsOneValueOnOneLine) {
  EXPECT_EQ(override_error("mesh.kind=graded\nmesh.n = 3"),
            "override 'mesh.kind': a value cannot contain a line break");
  EXPECT_EQ(override_error("mesh.n=3\r"), "override 'mesh.n': a value cannot contain a line break");
  EXPECT_EQ(override_error("mesh.kind=graded"), "");  // a bare word is a string
}

// The properties hold for every key keller declares: integer ranges fit int, finite defaults
// take no infinity, and the range of every `parameters.X` key lies inside the range of the
// problem's parameter X (so a value the scene accepts is never refused later without a line).
TEST(Scene, EveryDeclaredKeyObeysTheRules) {
  for (const ProblemType& type : problem_types()) {
    SCOPED_TRACE(type.name);
    SceneSchema s;
    declare_common_keys(s);
    type.declare(s);
    declare_trace_keys(s);
    for (const KeySpec& k : s.keys()) {
      if (k.type == KeySpec::Type::Integer) {
        EXPECT_GE(k.range.lo, std::numeric_limits<int>::min()) << k.path;
        EXPECT_LE(k.range.hi, std::numeric_limits<int>::max()) << k.path;
      }
      if (k.type == KeySpec::Type::Real) {
        const double d = std::get<double>(k.default_value);
        EXPECT_EQ(k.allows_infinity(), std::isinf(d)) << k.path;
      }
    }
    std::string text = "[problem]\ntype = \"" + type.name + "\"\n";
    if (type.name == "flow") {  // a flow needs a mesh and a condition on each of its boundaries
      const std::string msh = ::testing::TempDir() + "keller_scene_rules.msh";
      BlockMeshBuilder b;
      b.add_block({"channel",
                   "fluid",
                   2,
                   2,
                   Grading::uniform(),
                   Grading::uniform(),
                   [](double u, double v) {
                     return Mesh::Point{u, v};
                   },
                   {"bottom", "outflow", "top", "inflow"}});
      write_gmsh_mesh(b.build(), msh);
      text += "[mesh]\nfile = \"" + msh +
              "\"\n[boundaries.inflow]\ntype = \"inflow\"\n[boundaries.outflow]\ntype = \"outflow\"\n"
              "[boundaries.bottom]\ntype = \"wall\"\n[boundaries.top]\ntype = \"wall\"\n";
    }
    const Scene defaults = Scene::parse(text, type.name, s);
    const auto problem = type.build(defaults);
    for (const Parameter& p : problem->parameters().list()) {
      const KeySpec* key = s.find("parameters." + p.name);
      for (const KeySpec& k : s.keys())  // a problem may keep its parameter in its own section
        if (!key && k.key() == p.name && k.type == KeySpec::Type::Real) key = &k;
      ASSERT_NE(key, nullptr) << "parameter " << p.name << " has no scene key";
      Range range = p.range();
      if (range.lo == range.hi && key->path == "parameters." + p.name &&
          text.find("[parameters]") == std::string::npos) {
        // a parameter fixed at its scene value, where that value decides what is built (Re = 0: no
        // convective term): its range as built from another value the scene takes
        const double other = range.lo + 1.0;
        ASSERT_TRUE(key->range.contains(other)) << key->path;
        const auto built =
            type.build(Scene::parse(fmt::format("{}[parameters]\n{} = {}\n", text, p.name, other), type.name, s));
        range = built->parameters().list()[static_cast<size_t>(built->parameters().index(p.name))].range();
        EXPECT_TRUE(range.contains(range.lo + 1.0)) << key->path << " is fixed when built at " << other;
      }
      EXPECT_TRUE(key->range.within(range)) << "parameters." << p.name << ": the scene takes " << key->range.describe()
                                            << ", the parameter " << range.describe();
    }
  }
}

// The cylinder's element counts are capped (1000 around and across, 2000 along the channel, far
// inside int for the unknowns): a huge count is an error naming the key and its range, not an
// allocation failure; a size with a preset is refused, the W preset's grading can be changed.
TEST(Scene, CylinderMeshCountsAreCapped) {
  const std::string scene = test::source_path("runs/scenes/cylinder_oldroyd_b_log.toml");
  auto error = [&](std::vector<std::string> overrides) {
    try {
      const LoadedScene l = load_scene(scene, declare_trace_keys, overrides);
      (void)CylinderOptions::from_scene(l.scene);
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string custom = "mesh.name=custom";
  auto has = [](const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; };
  EXPECT_TRUE(
      has(error({custom, "mesh.n_quarter=100000", "mesh.n_radial=8", "mesh.nx_upstream=12", "mesh.nx_downstream=24"}),
          "key 'mesh.n_quarter' = 100000 is out of range: must be in [0, 1000]"));
  EXPECT_TRUE(
      has(error({custom, "mesh.n_quarter=8", "mesh.n_radial=8", "mesh.nx_upstream=12", "mesh.nx_downstream=2001"}),
          "key 'mesh.nx_downstream' = 2001 is out of range: must be in [0, 2000]"));
  EXPECT_TRUE(has(error({"mesh.n_rear=1001"}), "key 'mesh.n_rear' = 1001 is out of range: must be in [0, 1000]"));
  EXPECT_TRUE(has(error({"mesh.n_rear=32"}), "explicit sizes need mesh.name = \"custom\" (got \"W3\")"));
  EXPECT_EQ(error({custom, "mesh.n_quarter=1000", "mesh.n_radial=1000", "mesh.nx_upstream=2000",
                   "mesh.nx_downstream=2000", "mesh.n_rear=1000"}),
            "");
  const LoadedScene l = load_scene(scene, declare_trace_keys, {"mesh.wake_ratio=10"});
  const CylinderOptions o = CylinderOptions::from_scene(l.scene);
  EXPECT_EQ(o.mesh.name, "W3");
  EXPECT_EQ(o.mesh.n_rear, 48);
  EXPECT_EQ(o.mesh.wake_ratio, 10.0);
  EXPECT_EQ(o.mesh.rear_ratio, 4.0);
}

// Families of tables the scene names ([boundaries.<name>]) and of named numbers
// ([mesh.geo_parameters]): their members get concrete keys with the template's type, default and
// range; they survive the resolved scene; unknown keys inside a member are still errors.
namespace {

SceneSchema family_schema() {
  SceneSchema s = schema();
  s.section("boundaries.*", "a condition on a named boundary");
  s.string("boundaries.*.type", "", "kind of condition", {"", "wall", "inflow"});
  s.real_list("boundaries.*.velocity", {0.0, 0.0}, "a velocity");
  s.section("mesh.geo_parameters", "numbers passed to the .geo");
  s.real("mesh.geo_parameters.*", 0.0, "a number of the .geo", Range::positive());
  return s;
}

}  // namespace

TEST(Scene, FamilyMembersGetConcreteKeysAndDefaults) {
  const Scene s = Scene::parse(
      "[boundaries.inlet]\ntype = \"inflow\"\nvelocity = [1, 0]\n[boundaries.top-wall]\ntype = \"wall\"\n"
      "[boundaries.empty]\n[mesh.geo_parameters]\nratio = 4\nlc = 0.5\n",
      "s.toml", family_schema());
  EXPECT_EQ(s.members("boundaries"), (std::vector<std::string>{"empty", "inlet", "top-wall"}));
  EXPECT_EQ(s.string("boundaries.inlet.type"), "inflow");
  EXPECT_EQ(s.real_list("boundaries.inlet.velocity"), (std::vector<double>{1.0, 0.0}));
  EXPECT_EQ(s.real_list("boundaries.top-wall.velocity"), (std::vector<double>{0.0, 0.0}));  // the default
  EXPECT_EQ(s.string("boundaries.empty.type"), "");
  EXPECT_FALSE(s.given("boundaries.empty.type"));
  EXPECT_EQ(s.members("mesh.geo_parameters"), (std::vector<std::string>{"lc", "ratio"}));
  EXPECT_DOUBLE_EQ(s.real("mesh.geo_parameters.ratio"), 4.0);
  EXPECT_TRUE(Scene::parse("", "e.toml", family_schema()).members("boundaries").empty());
  EXPECT_THROW(s.real("mesh.geo_parameters.absent"), std::logic_error);  // never given: not a key
}

TEST(Scene, FamilyMembersSurviveTheResolvedSceneAndOverrides) {
  const Scene s = Scene::parse("[boundaries.inlet]\ntype = \"inflow\"\n[mesh.geo_parameters]\nratio = 4\n", "s.toml",
                               family_schema(), {"boundaries.outlet.type=wall", "mesh.geo_parameters.lc=0.25"});
  EXPECT_EQ(s.members("boundaries"), (std::vector<std::string>{"inlet", "outlet"}));
  EXPECT_DOUBLE_EQ(s.real("mesh.geo_parameters.lc"), 0.25);
  const Scene t = Scene::parse(s.resolved_toml(), "resolved", family_schema());
  EXPECT_EQ(t.canonical_values(), s.canonical_values());
  EXPECT_EQ(t.members("boundaries"), s.members("boundaries"));
  EXPECT_NE(s.canonical_values().find("boundaries.outlet.type = \"wall\"\n"), std::string::npos);
  EXPECT_EQ(s.canonical_values().find('*'), std::string::npos);  // templates are not values
  EXPECT_EQ(Scene::parse(s.non_default_toml(), "again", family_schema()).canonical_values(), s.canonical_values());
}

TEST(Scene, FamilyMembersAreValidatedLikeAnyKey) {
  auto error_in = [](const std::string& text) {
    try {
      Scene::parse(text, "s.toml", family_schema());
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error_in("[boundaries.inlet]\ntyp = \"wall\"\n"),
            "s.toml:2: unknown key 'boundaries.inlet.typ'; keys allowed in [boundaries.inlet]: type, velocity");
  EXPECT_EQ(error_in("[boundaries.inlet]\ntype = \"slip\"\n"),
            "s.toml:2: key 'boundaries.inlet.type' = \"slip\" is not one of: wall, inflow");
  EXPECT_EQ(error_in("[mesh.geo_parameters]\nratio = -1\n"),
            "s.toml:2: key 'mesh.geo_parameters.ratio' = -1 is out of range: must be > 0");
  EXPECT_EQ(error_in("[mesh.geo_parameters]\nratio = \"four\"\n"),
            "s.toml:2: key 'mesh.geo_parameters.ratio' must be a number, got a string (\"four\")");
  EXPECT_NE(error_in("[boundaries.\"*\"]\ntype = \"wall\"\n").find("unknown"), std::string::npos);
  EXPECT_NE(error_in("[boundaries.\"a b\"]\ntype = \"wall\"\n").find("unknown"), std::string::npos);
  EXPECT_NE(error_in("[boundaries.inlet.deeper]\ntype = \"wall\"\n").find("unknown"), std::string::npos);
}

// A file's path in a scene is relative to the scene file's folder, one from an override to the
// working directory; both are stored absolute, so that the scene an output holds, read back from
// anywhere, names the same file.
TEST(Scene, PathsAreRelativeToTheSceneFileAndStoredAbsolute) {
  SceneSchema s;
  s.section("mesh", "mesh");
  s.file_path("mesh.file", "a mesh");
  s.file_path("mesh.other", "another");
  const std::string dir = test::scratch_dir("scene_paths");
  std::ofstream(dir + "/s.toml") << "[mesh]\nfile = \"../meshes/x.msh\"\n";
  const Scene a = Scene::load(dir + "/s.toml", s, {"mesh.other=y.msh"});
  const fs::path scene_dir = fs::absolute(dir);
  EXPECT_EQ(a.string("mesh.file"), (scene_dir.parent_path() / "meshes/x.msh").lexically_normal().string());
  EXPECT_EQ(a.string("mesh.other"), (fs::current_path() / "y.msh").string());
  const Scene b = Scene::parse(a.resolved_toml(), "out.h5:/scene", s);  // as an output's stored scene
  EXPECT_EQ(b.string("mesh.file"), a.string("mesh.file"));
  EXPECT_EQ(b.canonical_values(), a.canonical_values());
  EXPECT_EQ(Scene::parse("[mesh]\nfile = \"/abs/x.msh\"\n", dir + "/s.toml", s).string("mesh.file"), "/abs/x.msh");
  EXPECT_EQ(Scene::parse("", "e.toml", s).string("mesh.file"), "");  // no path: stays empty
}
