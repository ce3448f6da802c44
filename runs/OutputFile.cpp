#include "runs/OutputFile.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <filesystem>
#include <stdexcept>

#include "core/SolutionWriter.hpp"

namespace keller {

void check_output_path(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path p(path);
  std::error_code ec;
  if (fs::is_directory(p, ec)) throw std::runtime_error(fmt::format("output '{}' is a directory", path));
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  if (!fs::is_directory(dir, ec)) throw std::runtime_error(fmt::format("output directory '{}' does not exist", dir.string()));
  if (access(dir.c_str(), W_OK) != 0)
    throw std::runtime_error(fmt::format("output directory '{}' is not writable", dir.string()));
}

std::string xdmf_path_for(const std::string& h5_path) {
  std::filesystem::path p(h5_path);
  p.replace_extension(".xdmf");
  return p.string();
}

void write_run_header(H5File& file, const Scene& scene, const Problem& problem) {
  file.write_string("/scene", scene.resolved_toml());
  file.set_attribute("/scene", "source", scene.source());
  file.create_group("/problem");
  file.set_attribute("/problem", "name", problem.name());
  file.set_attribute("/problem", "summary", problem.summary());
  file.set_attribute("/problem", "unknowns", static_cast<long>(problem.size()));
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
    for (size_t i = 0; i < names.size() && i < obs.size(); ++i) file.set_attribute(group + "/observables", names[i], obs[i]);
  }
  file.write_vector(group + "/u", std::vector<double>(u.data(), u.data() + u.size()));
}

}  // namespace keller
