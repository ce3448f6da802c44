#include "runs/OutputFile.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>

#include "core/IoError.hpp"
#include "core/OutputLock.hpp"
#include "core/PendingFile.hpp"
#include "core/SolutionWriter.hpp"
#include "runs/CommandFailure.hpp"
#include "runs/ExitCode.hpp"
#include "runs/Provenance.hpp"

namespace keller {

std::string xdmf_path_for(const std::string& h5_path) {
  std::filesystem::path p(h5_path);
  p.replace_extension(".xdmf");
  return p.string();
}

std::string text_hash(const std::string& text) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return fmt::format("{:016x}", h);
}

namespace {
std::map<std::string, std::string> record_lines(const std::string& record) {
  std::map<std::string, std::string> out;
  std::istringstream in(record);
  for (std::string line; std::getline(in, line);) {
    const auto eq = line.find(" = ");
    if (eq != std::string::npos) out[line.substr(0, eq)] = line.substr(eq + 3);
  }
  return out;
}

}  // namespace

bool records_agree(const std::string& stored, const std::string& now, const std::string& defaults) {
  if (stored == now) return true;
  return record_difference(stored, now, defaults).empty();
}

std::string record_difference(const std::string& stored, const std::string& now, const std::string& defaults) {
  const auto a = record_lines(stored), b = record_lines(now), d = record_lines(defaults);
  std::string out;
  auto add = [&](const std::string& s) { out += (out.empty() ? "" : "; ") + s; };
  for (const auto& [key, value] : a) {
    auto it = b.find(key);
    if (it == b.end())
      add(fmt::format("{} = {} in the file, not a key of this scene", key, value));
    else if (it->second != value)
      add(fmt::format("{} = {} in the file, {} in this scene", key, value, it->second));
  }
  for (const auto& [key, value] : b) {
    if (a.count(key)) continue;
    const auto def = d.find(key);
    if (def != d.end() && def->second == value) continue;  // added since, at its default
    add(fmt::format("{} = {} in this scene, not in the file", key, value));
  }
  return out;
}

void declare_run_outputs(RunFiles& files, const std::string& out, const std::string& what, bool with_fields) {
  const std::string work = PendingFile::temporary_for(out);
  files.output(what, out);
  files.temporary("unfinished " + what, work);
  files.temporary(what + "'s temporary", PendingFile::temporary_for(work));
  files.temporary(what + "'s copy with fields", out + ".fields.part");
  files.temporary(what + "'s lock", OutputLock::path_for(out));
  if (with_fields) declare_xdmf_outputs(files, out);
}

void declare_xdmf_outputs(RunFiles& files, const std::string& h5) {
  const auto declare = [&files](const std::string& role, const std::string& path) {
    files.output(role, path);
    files.temporary(role + "'s temporary", path + ".pending");
    files.temporary(role + "'s temporary", PendingFile::temporary_for(path + ".pending"));
  };
  const std::filesystem::path xdmf(xdmf_path_for(h5));
  declare("XDMF file", xdmf.string());
  // the eigenmodes' files, STEM_mode<k>.xdmf: those whose names (or temporary names) are taken
  // now, as a name that is free is no link
  const std::string prefix = xdmf.stem().string() + "_mode";
  std::set<std::string> modes;
  std::error_code ec;
  for (std::filesystem::directory_iterator it(xdmf.has_parent_path() ? xdmf.parent_path() : ".", ec), end;
       !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const size_t digits = name.rfind(prefix, 0) == 0 ? name.find_first_not_of("0123456789", prefix.size()) : 0;
    if (digits == 0 || digits == prefix.size() || digits == std::string::npos) continue;
    const std::string rest = name.substr(digits);
    if (rest == ".xdmf" || rest == ".xdmf.pending" || rest == ".xdmf.pending.part")
      modes.insert((xdmf.parent_path() / (name.substr(0, digits) + ".xdmf")).string());
  }
  for (const std::string& mode : modes) declare("eigenmode XDMF file", mode);
}

LeftRun left_run(const std::string& work, const std::string& record, const std::string& defaults, bool fresh,
                 const std::string& what, const std::string& unit, const std::string& code_dataset,
                 const UnfinishedTable& table) {
  LeftRun left;
  if (!std::filesystem::exists(work)) return left;
  std::string stored;
  std::optional<int> code;
  try {
    std::tie(left.rows, left.status) = table(work);
    H5File f(work, H5File::Mode::Read);
    if (f.exists("/problem/run")) stored = f.read_string("/problem/run");
    long marks = 0, cols = 0;
    const std::vector<double> marked =
        f.exists(code_dataset) ? f.read_matrix(code_dataset, &marks, &cols) : std::vector<double>{};
    if (!marked.empty() && marked.front() >= 0) code = static_cast<int>(marked.front());
  } catch (const std::exception&) {
    fmt::print("note: '{}' is not a readable {} file; this run replaces it\n", work, what);
    return left;
  }
  const bool unfinished = left.status == "running" || left.status.rfind("interrupted", 0) == 0;
  if (!unfinished && !(code && records_agree(stored, record, defaults))) {
    fmt::print("note: '{}' holds a {} that ended ({}); this run replaces it\n", work, what, left.status);
    return left;
  }
  if (fresh) {
    fmt::print("note: --fresh: the {} {} in '{}' ({} {}) is discarded\n", unfinished ? "unfinished" : "unpublished",
               what, work, left.rows, unit);
    return left;
  }
  if (!unfinished) {
    left.kind = LeftRun::Kind::ended;
    left.exit_code = *code;
    return left;
  }
  if (!records_agree(stored, record, defaults))
    throw std::invalid_argument(fmt::format(
        "'{}' holds the unfinished {} ({} {}) of another run ({}); move it away to keep it, or pass --fresh to "
        "discard it",
        work, what, left.rows, unit,
        stored.empty() ? "no record of its run" : "it differs in: " + record_difference(stored, record, defaults)));
  left.kind = LeftRun::Kind::unfinished;
  return left;
}

RunEnd write_run_file(const std::string& work, const std::string& out, const HeldFile& written, const std::string& what,
                      const std::string& unit, const std::function<RunEnd()>& run,
                      const std::function<void(std::optional<int>)>& finish) {
  std::optional<RunEnd> end;  // set once the run has ended
  bool takes = false;
  try {
    end = run();
    takes = takes_its_name(end->interrupted, end->failed, out);
    finish(takes ? std::optional<int>(end->failed ? exit_code::numerical_failure : exit_code::ok) : std::nullopt);
    return *end;
  } catch (const IoError& e) {
    // what `work` holds: its status is written with the publication code in one flush (finish), so
    // the same command either continues the run from its last point or publishes it
    std::string kept;
    if (written.at(work) && (!end || end->interrupted))
      kept = fmt::format("; every {} before it is kept in {}: run the same command again to continue the {}", unit,
                         work, what);
    else if (written.at(work) && takes)
      kept = fmt::format("; the ended {} is kept in {}: run the same command again to finish it", what, work);
    else if (written.at(work))
      kept = fmt::format("; {} is kept as it was, this run's {} is in {}", out, what, work);
    throw CommandFailure::io_failure(e.what() + kept);
  }
}

void expect_written(const std::string& work, const std::string& target, const HeldFile& written) {
  if (written.at(work)) return;
  std::string kept = "this run's file was moved elsewhere, with its content";
  if (!written.linked()) {
    const std::string saved = fmt::format("{}.{}", work, ::getpid());
    written.copy_to(saved);
    kept = fmt::format("this run's file is saved as '{}'", saved);
  }
  throw IoError(fmt::format(
      "'{}' is not the file this run wrote (it was replaced or removed during the run): '{}' and '{}' are left as "
      "they are; {}",
      work, target, work, kept));
}

void write_run_header(H5File& file, const LoadedScene& loaded, const Problem& problem) {
  file.write_string("/scene", loaded.scene.resolved_toml());
  file.set_attribute("/scene", "source", loaded.scene.source());
  file.create_group("/problem");
  file.set_attribute("/problem", "name", problem.name());
  file.set_attribute("/problem", "summary", problem.summary());
  file.set_attribute("/problem", "unknowns", static_cast<long>(problem.size()));
  const std::string physics = loaded.physics();
  file.write_string("/problem/physics", physics);
  file.set_attribute("/problem", "physics_hash", text_hash(physics));
  file.create_group("/problem/parameters");
  for (const Parameter& p : problem.parameters().list()) file.set_attribute("/problem/parameters", p.name, p.value);
  Provenance::current().write(file);
}

RunHeader read_run_header(const H5File& f) {
  RunHeader h;
  if (f.exists("/scene")) h.scene = f.read_string("/scene");
  if (!f.exists("/problem")) return h;
  if (f.has_attribute("/problem", "name")) h.problem = f.read_string_attribute("/problem", "name");
  if (f.has_attribute("/problem", "unknowns"))
    h.unknowns = static_cast<long>(f.read_double_attribute("/problem", "unknowns"));
  if (f.exists("/problem/physics")) h.physics = f.read_string("/problem/physics");
  if (f.has_attribute("/problem", "physics_hash")) h.physics_hash = f.read_string_attribute("/problem", "physics_hash");
  if (f.exists("/problem/parameters"))
    for (const std::string& name : f.attribute_names("/problem/parameters"))
      h.parameters[name] = f.read_double_attribute("/problem/parameters", name);
  return h;
}

void write_solution(H5File& file, const std::string& group, Problem& problem, const Vector& u) {
  const SolutionFields f = problem.fields(u);
  write_fields(file, group + "/fields", f);
  file.create_group(group + "/parameters");
  for (const Parameter& p : problem.parameters().list()) file.set_attribute(group + "/parameters", p.name, p.value);
  std::vector<double> obs;
  Status st = problem.observables(u, obs);
  file.create_group(group + "/observables");
  if (st.is_ok()) {
    const auto names = problem.observable_names();
    for (size_t i = 0; i < names.size() && i < obs.size(); ++i)
      file.set_attribute(group + "/observables", names[i], obs[i]);
  }
  file.write_vector(group + "/u", std::vector<double>(u.data(), u.data() + u.size()));
}

}  // namespace keller
