#include "continuation/output/TableRows.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "core/IoError.hpp"
#include "core/PendingFile.hpp"
#include "core/SignalPoint.hpp"
#include "core/SolutionWriter.hpp"

namespace keller {

namespace {
using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
}  // namespace

std::string join_names(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& x : names) s += (s.empty() ? "" : ",") + x;
  return s;
}

std::vector<std::string> split_names(const std::string& text) {
  std::vector<std::string> out;
  if (text.empty()) return out;
  size_t start = 0;
  for (;;) {
    const size_t pos = text.find(',', start);
    out.push_back(text.substr(start, pos - start));
    if (pos == std::string::npos) return out;
    start = pos + 1;
  }
}

Eigen::MatrixXd read_table_rows(const H5File& file, const std::string& dataset) {
  if (!file.exists(dataset)) return {};
  long r = 0, c = 0;
  const auto data = file.read_matrix(dataset, &r, &c);
  return Eigen::Map<const RowMajor>(data.data(), r, c);
}

void append_table_rows(H5File& file, const std::string& dataset, const Eigen::MatrixXd& m) {
  if (m.rows() == 0) return;
  const RowMajor r = m;
  file.append_rows(dataset, r.data(), r.rows());
}

void create_run_file(const std::string& path, const std::string& group, std::unique_ptr<H5File>& file,
                     HeldFile& written, const std::function<void()>& layout) {
  const std::string part = PendingFile::temporary_for(path);
  clear_leftover(part);
  file = std::make_unique<H5File>(part, H5File::Mode::Create);
  written = file->hold();
  try {
    layout();
    file->create_fixed_string(group + "/status", 2048);
    file->write_fixed_string(group + "/status", "running");
    file->create_appendable(group + "/exit_code", 1, 1);
    const double unmarked = -1;
    file->append_rows(group + "/exit_code", &unmarked, 1);
    file->start_swmr();
    file->flush();
    if (!written.at(part))
      throw IoError(fmt::format("'{}' is not the file this run created (it was replaced meanwhile)", part));
    if (std::rename(part.c_str(), path.c_str()) != 0)
      throw IoError(fmt::format("cannot rename '{}' to '{}': {}", part, path, std::strerror(errno)));
    file->renamed(path);
  } catch (...) {
    // this run's incomplete file: nothing of it is kept
    file.reset();
    std::error_code ec;
    if (written.at(part)) std::filesystem::remove(part, ec);
    throw;
  }
}

bool write_state_fields(const std::string& fields_path, bool in_place, long count,
                        const std::function<StoredState(long slot)>& state,
                        const std::function<SolutionFields(const StoredState&)>& fields, const std::string& xdmf_path,
                        const std::string& h5_name, const std::function<bool()>& stop) {
  H5File out(fields_path, in_place ? H5File::Mode::ReadWrite : H5File::Mode::Create);
  std::vector<XdmfSolution> steps;
  SolutionFields layout;
  for (long i = 0; i < count; ++i) {
    if (stop && stop()) return false;
    signal_point("fields");
    const StoredState s = state(i);
    SolutionFields sf = fields(s);
    if (!out.exists(s.group)) {  // written by an earlier run of this function: keep it
      write_fields(out, s.group, sf);
      out.set_attribute(s.group, s.index_name, s.index);
      out.set_attribute(s.group, s.value_name, s.value);
    }
    if (sf.mesh) {
      if (!out.exists("/mesh")) write_mesh(out, "/mesh", *sf.mesh);
      steps.push_back({s.group.substr(1), s.label, s.time});
      layout = sf;
    }
  }
  out.close();
  if (stop && stop()) return false;
  if (!steps.empty() && layout.mesh) write_xdmf(xdmf_path, h5_name, "mesh", *layout.mesh, steps, layout);
  return true;
}

}  // namespace keller
