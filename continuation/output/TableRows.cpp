#include "continuation/output/TableRows.hpp"

#include <algorithm>
#include <stdexcept>

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

int column_index(const std::vector<std::string>& columns, const std::string& name, const std::string& table) {
  auto it = std::find(columns.begin(), columns.end(), name);
  if (it == columns.end()) throw std::invalid_argument(table + " has no column '" + name + "'");
  return static_cast<int>(it - columns.begin());
}

void check_seed(const std::string& what, const std::vector<std::string>& seed_columns,
                const std::vector<std::string>& columns, const Eigen::MatrixXd& states, long n) {
  if (seed_columns != columns)
    throw std::runtime_error("the unfinished " + what + " has other columns than this run's (" +
                             join_names(seed_columns) + ")");
  if (states.rows() > 0 && states.cols() != n)
    throw std::runtime_error("the unfinished " + what + " has another number of unknowns");
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
