#include "runs/study/Study.hpp"

#include <fmt/format.h>

#include <toml++/toml.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <sstream>

#include "continuation/engine/ContinuationOptions.hpp"
#include "continuation/orbits/OrbitContinuation.hpp"
#include "continuation/output/BranchFile.hpp"
#include "core/Scene.hpp"
#include "runs/OutputFile.hpp"
#include "runs/SceneLoader.hpp"
#include "runs/SolveCommand.hpp"
#include "runs/TraceCommand.hpp"
#include "runs/study/TaskScenes.hpp"
#include "stability/StabilityAnalysis.hpp"

namespace keller {

namespace fs = std::filesystem;

std::string StudyTask::label() const {
  std::string s;
  for (const auto& [k, v] : varied) s += (s.empty() ? "" : ", ") + k + "=" + v;
  return s.empty() ? "the base scene" : s;
}

namespace {

struct Value {
  std::string text;  // as TOML
  int line = 0;
};
using Assignments = std::vector<std::pair<std::string, Value>>;

std::string toml_text(const toml::node& n) {
  if (const auto s = n.value_exact<std::string>()) {
    std::string out = "\"";
    for (char c : *s) {
      if (c == '"' || c == '\\') out += '\\';
      out += c;
    }
    return out + "\"";
  }
  if (const auto d = n.value_exact<double>()) {
    std::string s = fmt::format("{}", *d);
    if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
    return s;
  }
  if (const auto i = n.value_exact<int64_t>()) return fmt::format("{}", *i);
  if (const auto b = n.value_exact<bool>()) return *b ? "true" : "false";
  if (const toml::array* a = n.as_array()) {
    std::string s = "[";
    for (size_t i = 0; i < a->size(); ++i) s += (i ? ", " : "") + toml_text(*a->get(i));
    return s + "]";
  }
  std::ostringstream os;
  n.visit([&](auto&& x) { os << x; });
  return os.str();
}

// The leaves of a table as dotted paths ("fluid.model" written quoted or as nested tables).
void leaves(const toml::table& t, const std::string& prefix, Assignments& out) {
  for (auto&& [k, v] : t) {
    const std::string path = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (const toml::table* sub = v.as_table())
      leaves(*sub, path, out);
    else
      out.push_back({path, {toml_text(v), static_cast<int>(v.source().begin.line)}});
  }
}

// The leaves of [grid]: each an array of the values it takes.
std::vector<std::pair<std::string, std::vector<Value>>> grid_leaves(const toml::table& t, const std::string& prefix,
                                                                    const std::string& file) {
  std::vector<std::pair<std::string, std::vector<Value>>> out;
  for (auto&& [k, v] : t) {
    const std::string path = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (const toml::table* sub = v.as_table()) {
      auto inner = grid_leaves(*sub, path, file);
      out.insert(out.end(), inner.begin(), inner.end());
      continue;
    }
    const toml::array* a = v.as_array();
    const int line = static_cast<int>(v.source().begin.line);
    if (!a || a->empty())
      throw SceneError(
          fmt::format("{}:{}: [grid] key '{}' must be a non-empty list of the values it takes", file, line, path));
    std::vector<Value> values;
    for (const toml::node& e : *a) values.push_back({toml_text(e), line});
    out.push_back({path, std::move(values)});
  }
  return out;
}

std::string unquoted(const std::string& v) {
  if (v.size() >= 2 && v.front() == '"' && v.back() == '"') return v.substr(1, v.size() - 2);
  return v;
}

// A file-name-safe rendering of the varied values, with a hash that keeps names apart.
std::string task_name(const std::vector<std::pair<std::string, std::string>>& varied) {
  if (varied.empty()) return "task";
  std::string name, all;
  for (const auto& [k, v] : varied) {
    std::string part;
    for (char c : unquoted(v))
      part += (std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '+') ? c : '_';
    if (part.size() > 24) part.resize(24);
    name += (name.empty() ? "" : "_") + part;
    all += k + "=" + v + "\n";
  }
  return name + "-" + text_hash(all).substr(0, 8);
}

const std::set<std::string> special_keys = {"scene", "start"};

}  // namespace

std::optional<PointKind> collected_event_kind(const std::string& name) {
  if (name == "fold") return PointKind::Fold;
  if (name == "bp" || name == "branch-point") return PointKind::BranchPoint;
  if (name == "hopf") return PointKind::Hopf;
  if (name == "pd" || name == "period-doubling") return PointKind::PeriodDoubling;
  if (name == "ns" || name == "neimark-sacker") return PointKind::NeimarkSacker;
  return std::nullopt;
}

std::vector<std::string> Study::varied_keys() const { return varied_keys_; }
std::string Study::task_output(const StudyTask& t) const { return folder_ + "/tasks/" + t.name + ".h5"; }
std::string Study::task_log(const StudyTask& t) const { return folder_ + "/tasks/" + t.name + ".log"; }
std::string Study::task_record(const StudyTask& t) const { return folder_ + "/tasks/" + t.name + ".toml"; }
std::string Study::table_h5() const { return folder_ + "/" + name_ + ".h5"; }
std::string Study::table_csv() const { return folder_ + "/" + name_ + ".csv"; }

Study Study::load(const std::string& path, const std::string& folder, int only) {
  std::ifstream in(path, std::ios::binary);
  if (!fs::is_regular_file(path) || !in) throw SceneError(fmt::format("study file '{}' cannot be read", path));
  std::stringstream ss;
  ss << in.rdbuf();
  toml::table doc;
  try {
    doc = toml::parse(ss.str(), path);
  } catch (const toml::parse_error& e) {
    throw SceneError(fmt::format("{}:{}:{}: not valid TOML: {}", path, e.source().begin.line, e.source().begin.column,
                                 e.description()));
  }
  auto error = [&](const toml::node& n, const std::string& what) {
    return SceneError(fmt::format("{}:{}: {}", path, n.source().begin.line, what));
  };
  for (auto&& [k, v] : doc) {
    const std::string key(k.str());
    if (key != "study" && key != "set" && key != "grid" && key != "cases" && key != "collect")
      throw error(v,
                  fmt::format("unknown section [{}]; a study has [study], [set], [grid], [[cases]], [collect]", key));
  }
  Study s;
  s.path_ = path;
  s.name_ = fs::path(path).stem().string();
  s.folder_ = folder.empty() ? s.name_ : folder;
  const fs::path here = fs::path(path).parent_path();
  auto relative_to_study = [&](const std::string& p) {
    return fs::path(p).is_absolute() ? p : (here / p).lexically_normal().string();
  };

  const toml::table* study = doc["study"].as_table();
  if (!study) throw SceneError(fmt::format("{}: a study needs a [study] section with its base scene", path));
  std::string base, start;
  s.kind_ = "trace";
  for (auto&& [k, v] : *study) {
    const std::string key(k.str());
    const auto text = v.value_exact<std::string>();
    if (key != "scene" && key != "task" && key != "start")
      throw error(v, fmt::format("unknown key 'study.{}'; keys allowed in [study]: scene, task, start", key));
    if (!text) throw error(v, fmt::format("key 'study.{}' must be a string", key));
    if (key == "scene") base = relative_to_study(*text);
    if (key == "task") {
      if (*text != "trace" && *text != "solve" && *text != "orbit")
        throw error(v, fmt::format("key 'study.task' = \"{}\" is not one of: trace, solve, orbit", *text));
      s.kind_ = *text;
    }
    if (key == "start") start = *text;
  }
  if (base.empty()) throw SceneError(fmt::format("{}: key 'study.scene' (the base scene) is missing", path));

  Assignments fixed;
  if (const toml::node_view set = doc["set"]) {
    if (!set.as_table()) throw error(*set.node(), "[set] must be a table of scene keys");
    leaves(*set.as_table(), "", fixed);
  }
  for (const auto& [k, v] : fixed)
    if (special_keys.count(k))
      throw SceneError(fmt::format("{}:{}: '{}' is set in [study], not in [set]", path, v.line, k));

  std::vector<Assignments> cases;
  if (const toml::node_view c = doc["cases"]) {
    const toml::array* a = c.as_array();
    if (!a || !a->is_array_of_tables()) throw error(*c.node(), "[[cases]] must be tables of scene keys");
    for (const toml::node& t : *a) {
      Assignments one;
      leaves(*t.as_table(), "", one);
      cases.push_back(std::move(one));
    }
  }
  std::vector<std::pair<std::string, std::vector<Value>>> grid;
  if (const toml::node_view g = doc["grid"]) {
    if (!g.as_table()) throw error(*g.node(), "[grid] must be a table of lists");
    grid = grid_leaves(*g.as_table(), "", path);
  }
  if (const toml::node_view c = doc["collect"]) {
    if (!c.as_table()) throw error(*c.node(), "[collect] must be a table");
    for (auto&& [k, v] : *c.as_table()) {
      const std::string key(k.str());
      std::vector<std::string>* list = key == "events"  ? &s.collect_.events
                                       : key == "stops" ? &s.collect_.stops
                                       : key == "end"   ? &s.collect_.end
                                                        : nullptr;
      if (!list)
        throw error(v, fmt::format("unknown key 'collect.{}'; keys allowed in [collect]: events, stops, end", key));
      const toml::array* a = v.as_array();
      if (!a) throw error(v, fmt::format("key 'collect.{}' must be a list of names", key));
      for (const toml::node& e : *a) {
        const auto name = e.value_exact<std::string>();
        if (!name) throw error(e, fmt::format("key 'collect.{}' must be a list of names", key));
        list->push_back(*name);
      }
    }
  }

  // the tasks: every case with every grid point (one empty case when there are none), the last
  // key of [grid] varying fastest
  if (cases.empty()) cases.push_back({});
  for (const Assignments& c : cases)
    for (const auto& [k, v] : c)
      if (std::find(s.varied_keys_.begin(), s.varied_keys_.end(), k) == s.varied_keys_.end())
        s.varied_keys_.push_back(k);
  for (const auto& [key, values] : grid)
    if (std::find(s.varied_keys_.begin(), s.varied_keys_.end(), key) == s.varied_keys_.end())
      s.varied_keys_.push_back(key);
  double count = static_cast<double>(cases.size());
  for (const auto& [key, values] : grid) count *= static_cast<double>(values.size());
  if (count > std::numeric_limits<int>::max())
    throw SceneError(
        fmt::format("{}: {:.0f} tasks; a study has at most {}", path, count, std::numeric_limits<int>::max()));
  s.count_ = static_cast<int>(count);
  const auto make_task = [&](int index) {
    StudyTask t;
    t.index = index;
    t.scene = base;
    t.start = start;
    Assignments point;  // the grid's values of this task
    for (size_t k = grid.size(), rest = static_cast<size_t>(index); k-- > 0;) {
      const auto& [key, values] = grid[k];
      point.insert(point.begin(), {key, values[rest % values.size()]});
      rest /= values.size();
    }
    size_t per_case = 1;
    for (const auto& [key, values] : grid) per_case *= values.size();
    const Assignments& c = cases[static_cast<size_t>(index) / per_case];
    Assignments all = fixed;
    all.insert(all.end(), c.begin(), c.end());
    all.insert(all.end(), point.begin(), point.end());
    for (const auto& [k, v] : c) t.varied.push_back({k, v.text});
    for (const auto& [k, v] : point) t.varied.push_back({k, v.text});
    for (const auto& [k, v] : all) {
      if (k == "scene")
        t.scene = relative_to_study(unquoted(v.text));
      else if (k == "start")
        t.start = unquoted(v.text);
      else
        t.overrides.push_back(k + "=" + v.text);
    }
    if (!t.start.empty() && s.kind_ == "solve")
      throw SceneError(fmt::format("{}: task {} ({}): a start from a stored point needs task = \"trace\"", path,
                                   t.index, t.label()));
    if (t.start.empty() && s.kind_ == "orbit")
      throw SceneError(
          fmt::format("{}: task {} ({}): an orbit branch starts at a located Hopf point: set study.start "
                      "= \"BRANCH.h5:hopf1\" (or start in its case)",
                      path, t.index, t.label()));
    if (!t.start.empty()) {
      const auto colon = t.start.rfind(':');
      if (colon != std::string::npos) t.start = relative_to_study(t.start.substr(0, colon)) + t.start.substr(colon);
    }
    t.name = task_name(t.varied);
    return t;
  };
  if (only >= 0) {  // the process that runs one task: that task alone (its study checked the others)
    if (only < s.count_) s.tasks_.push_back(make_task(only));
  } else {
    std::set<std::string> names;
    for (int i = 0; i < s.count_; ++i) {
      StudyTask t = make_task(i);
      if (!names.insert(t.name).second)
        throw SceneError(fmt::format("{}: task {} ({}) is the same as an earlier one", path, t.index, t.label()));
      s.tasks_.push_back(std::move(t));
    }
  }
  s.check_tasks();
  return s;
}

void Study::check_tasks() {
  // validated like --set, before any task runs
  TaskScenes scenes(kind_);
  std::map<std::string, int> runs;  // the tasks by the hash of their run record
  const size_t n = tasks_.size();
  const bool many = n >= 10000;
  const auto t0 = std::chrono::steady_clock::now();
  auto seconds = [&]() { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  double said = 0;
  if (many) fmt::print(stderr, "study {}: checking the {} tasks of {} (each like --set)\n", name_, n, path_);
  for (StudyTask& t : tasks_) {
    try {
      const LoadedScene loaded = scenes.load(t);
      t.hash = text_hash(scenes.run_record(t, loaded));
      t.shape = scenes.shape(loaded);
      t.problem = TaskScenes::problem(loaded);
    } catch (const SceneError& e) {
      throw SceneError(fmt::format("{}: task {} ({}): {}", path_, t.index, t.label(), e.what()));
    }
    if (const auto [it, fresh] = runs.emplace(t.hash, t.index); !fresh) {
      const StudyTask& first = tasks_[static_cast<size_t>(it->second)];
      throw SceneError(fmt::format(
          "{}: task {} ({}) is the same run as task {} ({}): every key resolves to the same value; a study runs "
          "each run once (remove one of the values or cases)",
          path_, t.index, t.label(), first.index, first.label()));
    }
    if (many && seconds() - said >= 10) {
      said = seconds();
      const double left = said / (t.index + 1) * static_cast<double>(n - static_cast<size_t>(t.index) - 1);
      fmt::print(stderr, "study {}: {} of {} tasks checked, about {:.0f} s left\n", name_, t.index + 1, n, left);
    }
  }
  if (many) fmt::print(stderr, "study {}: checked {} tasks in {:.1f} s\n", name_, n, seconds());
}

TaskRunRecord Study::run_record(const StudyTask& t) const {
  TaskScenes scenes(kind_);
  const LoadedScene loaded = scenes.load(t);
  return {scenes.run_record(t, loaded), loaded.defaults()};
}

bool Study::record_agrees(const StudyTask& t, const std::string& stored, std::string* difference) const {
  if (!t.hash.empty() && text_hash(stored) == t.hash) return true;
  TaskRunRecord now;
  try {
    now = run_record(t);
  } catch (const SceneError& e) {
    if (difference) *difference = e.what();
    return false;
  }
  if (records_agree(stored, now.record, now.defaults)) return true;
  if (difference) *difference = record_difference(stored, now.record, now.defaults);
  return false;
}

void Study::check_collect() const {
  // what shapes the names: the physics (the problem's observables and monitors), and for a trace
  // the parameter, the stop observable and its thresholds, and the stability columns
  std::set<std::string> checked;
  TaskScenes scenes(kind_);
  for (const StudyTask& t : tasks_) {
    if (!checked.insert(t.shape).second) continue;
    std::vector<std::string> observables, monitors, columns;
    std::string stop;  // the stop observable, whose crossing of its threshold is an event too
    try {
      const LoadedScene loaded = scenes.load(t);
      std::optional<ContinuationOptions> o;
      StabilityOptions stability;
      if (kind_ != "solve") {
        o = ContinuationOptions::from_scene(loaded.scene);
        stop = o->stop.observable;
        stability = StabilityOptions::from_scene(loaded.scene);
      }
      const std::unique_ptr<Problem> problem = loaded.type->build(loaded.scene);
      observables = problem->observable_names();
      monitors = problem->monitor_names();
      if (o && kind_ == "orbit") {
        // an orbit branch's table: period, amplitude, each observable at u0 and its amplitude, the
        // multipliers; no monitors
        observables = OrbitContinuation::observable_names(observables);
        monitors.clear();
        stop.clear();
        columns = branch_table_columns(
            o->parameter, observables, monitors,
            OrbitContinuation::analysis_columns(OrbitContinuationOptions::from_scene(loaded.scene, *o).multipliers));
      } else if (o) {
        // the run's monitors: the problem's, then the stop observable's thresholds (Continuation)
        for (const std::string& m : o->stop.threshold_monitor_names()) monitors.push_back(m);
        const std::vector<std::string> analysis =
            stability.enabled ? StabilityAnalysis(stability).column_names() : std::vector<std::string>{};
        columns = branch_table_columns(o->parameter, observables, monitors, analysis);
      }
    } catch (const std::exception&) {
      continue;  // a problem that cannot be built fails when its task runs, and says why there
    }
    const auto has = [](const std::vector<std::string>& v, const std::string& n) {
      return std::find(v.begin(), v.end(), n) != v.end();
    };
    const auto column = [&](const std::string& n) { return has(observables, n) || has(columns, n); };
    const auto orbit_event = [&](const std::string& n) {
      const auto k = collected_event_kind(n);
      return k && *k != PointKind::Hopf;
    };
    const auto event = [&](const std::string& n) {
      const auto k = collected_event_kind(n);
      if (k) return *k == PointKind::Fold || *k == PointKind::BranchPoint || *k == PointKind::Hopf;
      return has(monitors, n) || (!stop.empty() && n == stop);
    };
    const auto check = [&](const char* key, const std::vector<std::string>& names, const auto& known,
                           const std::string& what) {
      for (const std::string& n : names)
        if (!known(n))
          throw SceneError(fmt::format("{}: [collect] {} names '{}', which task {} ({}) will not have; {}", path_, key,
                                       n, t.index, t.label(), what));
    };
    const std::string listed = fmt::format("its observables: {}", fmt::join(observables, ", "));
    if (kind_ == "orbit") {
      check("events", collect_.events, orbit_event,
            "an orbit branch's events are fold, branch-point, period-doubling (pd) and neimark-sacker (ns)");
      check("stops", collect_.stops, column, listed);
    } else if (kind_ == "trace") {
      check("events", collect_.events, event,
            fmt::format("events are fold, branch-point, hopf, a monitor ({}) or the stop observable ({})",
                        monitors.empty() ? "none" : fmt::format("{}", fmt::join(monitors, ", ")),
                        stop.empty() ? "none" : stop));
      check("stops", collect_.stops, column, listed);
    } else if (!collect_.events.empty() || !collect_.stops.empty()) {
      throw SceneError(fmt::format("{}: [collect] events and stops are a trace's; a solve collects only end", path_));
    }
    check("end", collect_.end, column, listed);
  }
}

}  // namespace keller
