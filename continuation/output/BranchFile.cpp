#include "continuation/output/BranchFile.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "continuation/output/TableRows.hpp"
#include "core/RunFiles.hpp"
#include "core/SignalPoint.hpp"
#include "core/SolutionWriter.hpp"

namespace keller {

namespace {

constexpr const char* kKinds = "0 point, 1 start, 2 stop, 3 event, 4 fold, 5 bp, 6 end, 7 hopf, 8 pd, 9 ns";

// /branch/events: a row per located point, its monitor as an index into the monitors attribute
// (-1: none). The writer's record and the reader's decoding of it.
constexpr const char* kEventColumns = "row,kind,parameter,monitor";

std::array<double, 4> event_record(const BranchPoint& p, const std::vector<std::string>& monitors) {
  double monitor = -1;  // an event's monitor, and an end's when a monitor's threshold ended the branch
  if (p.kind == PointKind::Event || p.kind == PointKind::End) {
    auto it = std::find(monitors.begin(), monitors.end(), p.label);
    if (it != monitors.end()) monitor = static_cast<double>(it - monitors.begin());
  }
  return {static_cast<double>(p.index), static_cast<double>(p.kind), p.lambda, monitor};
}

std::vector<BranchEvent> read_events(const H5File& f, const std::vector<std::string>& monitors) {
  const Eigen::MatrixXd records = read_table_rows(f, "/branch/events");
  std::vector<BranchEvent> events;
  for (long i = 0; i < records.rows() && records.cols() >= 4; ++i) {
    BranchEvent e;
    e.row = static_cast<int>(records(i, 0));
    e.kind = static_cast<PointKind>(static_cast<int>(records(i, 1)));
    e.parameter = records(i, 2);
    const int m = static_cast<int>(records(i, 3));
    if (m >= 0 && m < static_cast<int>(monitors.size())) e.monitor = monitors[static_cast<size_t>(m)];
    events.push_back(std::move(e));
  }
  return events;
}

}  // namespace

std::vector<std::string> branch_table_columns(const std::string& parameter, const std::vector<std::string>& observables,
                                              const std::vector<std::string>& monitors,
                                              const std::vector<std::string>& analysis) {
  std::vector<std::string> c = {"row", "kind", "s", parameter};
  c.insert(c.end(), observables.begin(), observables.end());
  for (const auto& m : monitors) c.push_back("monitor:" + m);
  c.insert(c.end(), analysis.begin(), analysis.end());
  for (const char* name : {"iterations", "step", "seconds", "det_sign", "tangent_parameter", "saved_slot"})
    c.push_back(name);
  return c;
}

std::vector<std::string> normal_form_columns(const std::vector<std::string>& observables) {
  std::vector<std::string> columns = {"type",
                                      "exact",
                                      "a",
                                      "b",
                                      "c",
                                      "curvature",
                                      "cubic",
                                      "growth_rate_derivative",
                                      "omega",
                                      "period",
                                      "l1",
                                      "c1_re",
                                      "c1_im",
                                      "amplitude_coefficient",
                                      "amplitude_entry",
                                      "side",
                                      "seconds"};
  for (const std::string& o : observables) columns.push_back("amplitude:" + o);
  return columns;
}

const std::vector<std::string>& normal_form_types() {
  static const std::vector<std::string> types = {"fold",
                                                 "transcritical",
                                                 "pitchfork (supercritical)",
                                                 "pitchfork (subcritical)",
                                                 "isolated point",
                                                 "Hopf (supercritical)",
                                                 "Hopf (subcritical)",
                                                 "cusp",
                                                 "Bogdanov-Takens",
                                                 "fold-Hopf"};
  return types;
}

BranchFile::BranchFile(const std::string& path, const Problem& problem, const ContinuationOptions& options,
                       const std::vector<std::string>& monitor_names, double state_scale,
                       const std::function<void(H5File&)>& header, const std::vector<std::string>& analysis_columns,
                       const BranchSeed* seed)
    : n_(problem.size()),
      columns_(branch_table_columns(options.parameter, problem.observable_names(), monitor_names, analysis_columns)),
      monitors_(monitor_names),
      n_analysis_(analysis_columns.size()),
      n_normal_form_(normal_form_columns(problem.observable_names()).size()),
      run_(path, "/branch", [&](H5File& f) {
        if (header) header(f);
        f.create_group("/branch");
        f.set_attribute("/branch", "parameter", options.parameter);
        f.set_attribute("/branch", "columns", join_names(columns_));
        f.set_attribute("/branch", "observables", join_names(problem.observable_names()));
        f.set_attribute("/branch", "monitors", join_names(monitor_names));
        f.set_attribute("/branch", "kinds", std::string(kKinds));
        f.set_attribute("/branch", "state_scale", state_scale);
        f.set_attribute("/branch", "theta", options.theta);
        f.set_attribute(
            "/branch", "method",
            std::string(options.method == ContinuationOptions::Method::Arclength ? "arclength" : "natural"));
        f.create_appendable("/branch/table", static_cast<long>(columns_.size()));
        f.create_appendable("/branch/saved", 6, 16);
        f.set_attribute("/branch/saved", "columns", std::string("row,kind,parameter,tangent_parameter,step,s"));
        f.create_appendable("/branch/solutions", n_, 1);
        f.create_appendable("/branch/tangents", n_, 1);
        f.create_appendable("/branch/events", 4, 16);
        f.set_attribute("/branch/events", "columns", std::string(kEventColumns));
        f.create_appendable("/branch/normal_forms", static_cast<long>(n_normal_form_) + 2, 16);
        f.set_attribute("/branch/normal_forms", "columns",
                        "row,kind," + join_names(normal_form_columns(problem.observable_names())));
        f.set_attribute("/branch/normal_forms", "types", join_names(normal_form_types()));
        if (n_analysis_) {
          f.create_appendable("/branch/eigenvectors", n_, 1);
          f.create_appendable("/branch/eigenvector_rows", 4, 16);
          f.set_attribute("/branch/eigenvector_rows", "columns", std::string("row,kind,sigma_re,sigma_im"));
        }
        if (seed) write_seed(f, *seed);
      }) {}

void BranchFile::write_seed(H5File& f, const BranchSeed& seed) {
  check_seed("branch", seed.columns, columns_, seed.solutions, n_);
  append_table_rows(f, "/branch/table", seed.table);
  append_table_rows(f, "/branch/saved", seed.saved);
  append_table_rows(f, "/branch/solutions", seed.solutions);
  append_table_rows(f, "/branch/tangents", seed.tangents);
  append_table_rows(f, "/branch/events", seed.events);
  append_table_rows(f, "/branch/normal_forms", seed.normal_forms);
  if (n_analysis_) {
    append_table_rows(f, "/branch/eigenvectors", seed.eigenvectors);
    append_table_rows(f, "/branch/eigenvector_rows", seed.eigenvector_rows);
    if (seed.eigenvector_rows.rows() > 0)
      last_mode_row_ = static_cast<int>(seed.eigenvector_rows(seed.eigenvector_rows.rows() - 1, 0));
  }
  saved_ = static_cast<int>(seed.saved.rows());
  last_saved_row_ = seed.row;
}

void BranchFile::save_solution(const BranchPoint& p) {
  run_.h5().append_rows("/branch/solutions", p.u.data(), 1);
  run_.h5().append_rows("/branch/tangents", p.tu.data(), 1);
  const double row[6] = {static_cast<double>(p.index), static_cast<double>(p.kind), p.lambda, p.tlambda, p.step, p.s};
  run_.h5().append_rows("/branch/saved", row, 1);
  last_saved_row_ = p.index;
  ++saved_;
}

void BranchFile::on_point(const BranchPoint& p) {
  if (!run_.is_open()) return;
  const int slot = p.save ? saved_ : -1;
  if (p.save) save_solution(p);
  if (p.save && n_analysis_) save_mode(p);  // the critical eigenvector with every stored solution
  std::vector<double> row = {static_cast<double>(p.index), static_cast<double>(p.kind), p.s, p.lambda};
  row.insert(row.end(), p.observables.begin(), p.observables.end());
  row.insert(row.end(), p.monitors.begin(), p.monitors.end());
  for (size_t i = 0; i < n_analysis_; ++i) row.push_back(i < p.analysis.size() ? p.analysis[i] : NAN);
  row.insert(row.end(), {static_cast<double>(p.iterations), p.step, p.seconds, static_cast<double>(p.det_sign),
                         p.tlambda, static_cast<double>(slot)});
  if (row.size() != columns_.size())
    throw std::logic_error(fmt::format("branch row has {} values for {} columns", row.size(), columns_.size()));
  run_.h5().append_rows("/branch/table", row.data(), 1);
  if (p.kind != PointKind::Regular && p.kind != PointKind::Start) {
    run_.h5().append_rows("/branch/events", event_record(p, monitors_).data(), 1);
    const bool critical = p.kind == PointKind::Fold || p.kind == PointKind::BranchPoint || p.kind == PointKind::Hopf;
    if (n_analysis_ && critical) save_mode(p);
    if (p.normal_form.size() == n_normal_form_) {  // a critical point's, or a curve's event's (a cusp)
      std::vector<double> nf = {static_cast<double>(p.index), static_cast<double>(p.kind)};
      nf.insert(nf.end(), p.normal_form.begin(), p.normal_form.end());
      run_.h5().append_rows("/branch/normal_forms", nf.data(), 1);
    }
  }
  run_.h5().flush();
  signal_point("point");
}

void BranchFile::save_mode(const BranchPoint& p) {
  if (p.critical_re.size() != n_ || p.index == last_mode_row_) return;  // none, or stored already
  last_mode_row_ = p.index;
  const Vector im = p.critical_im.size() == n_ ? p.critical_im : Vector::Zero(n_);
  run_.h5().append_rows("/branch/eigenvectors", p.critical_re.data(), 1);
  run_.h5().append_rows("/branch/eigenvectors", im.data(), 1);
  const double er[4] = {static_cast<double>(p.index), static_cast<double>(p.kind), p.locator, p.critical_imag};
  run_.h5().append_rows("/branch/eigenvector_rows", er, 1);
}

void BranchFile::on_finish(const std::string& reason, const BranchPoint& last) {
  if (!run_.is_open()) return;
  // the last point is always stored (for restarts); /branch/saved lists it
  if (last.index >= 0 && last.index != last_saved_row_ && last.u.size() == n_) save_solution(last);
  run_.ended(reason);
}

int BranchTable::column(const std::string& name) const { return column_index(columns, name, "branch table"); }

std::string BranchTable::located_monitor(int row) const {
  for (const BranchEvent& e : events)
    if (e.row == row && !e.monitor.empty()) return e.monitor;
  return {};
}

BranchTable read_branch_table(const std::string& path) {
  H5File f(path, H5File::Mode::Read);
  if (!f.exists("/branch/table")) throw std::runtime_error("'" + path + "' is not a branch file (no /branch/table)");
  BranchTable t;
  t.parameter = f.read_string_attribute("/branch", "parameter");
  t.columns = split_names(f.read_string_attribute("/branch", "columns"));
  t.observables = split_names(f.read_string_attribute("/branch", "observables"));
  t.monitors = split_names(f.read_string_attribute("/branch", "monitors"));
  t.state_scale = f.read_double_attribute("/branch", "state_scale");
  t.theta = f.read_double_attribute("/branch", "theta");
  t.status = f.read_string("/branch/status");
  long r = 0, c = 0;
  const auto data = f.read_matrix("/branch/table", &r, &c);
  t.rows.resize(r, c);
  for (long i = 0; i < r; ++i)
    for (long j = 0; j < c; ++j) t.rows(i, j) = data[static_cast<size_t>(i * c + j)];
  const auto saved = f.read_matrix("/branch/saved", &r, &c);
  // a killed run may have appended a solution whose table row never got written: keep only
  // solutions whose row exists
  for (long i = 0; i < r; ++i) t.saved_rows.push_back(static_cast<int>(saved[static_cast<size_t>(i * c)]));
  t.events = read_events(f, t.monitors);
  return t;
}

BranchPoint read_branch_point(const std::string& path, int row) {
  H5File f(path, H5File::Mode::Read);
  long r = 0, c = 0;
  const auto saved = f.read_matrix("/branch/saved", &r, &c);
  long solutions = 0, n = 0;
  f.read_matrix("/branch/solutions", &solutions, &n);
  long tangents = 0;
  f.read_matrix("/branch/tangents", &tangents, nullptr);
  const long usable = std::min({r, solutions, tangents});
  if (usable == 0) throw std::invalid_argument("'" + path + "' holds no stored solution");
  long slot = -1;
  if (row < 0) {
    slot = usable - 1;
  } else {
    for (long i = 0; i < usable; ++i)
      if (static_cast<int>(saved[static_cast<size_t>(i * c)]) == row) slot = i;
  }
  if (slot < 0) {
    std::string rows;
    for (long i = 0; i < usable; ++i)
      rows += (rows.empty() ? "" : ", ") + std::to_string(static_cast<int>(saved[i * c]));
    throw std::invalid_argument(fmt::format("row {} of '{}' has no stored solution; stored rows: {}", row, path, rows));
  }
  const auto U = f.read_matrix("/branch/solutions", &solutions, &n);
  const auto T = f.read_matrix("/branch/tangents", nullptr, nullptr);
  BranchPoint p;
  p.index = static_cast<int>(saved[static_cast<size_t>(slot * c)]);
  p.kind = static_cast<PointKind>(static_cast<int>(saved[static_cast<size_t>(slot * c + 1)]));
  p.lambda = saved[static_cast<size_t>(slot * c + 2)];
  p.tlambda = saved[static_cast<size_t>(slot * c + 3)];
  p.step = saved[static_cast<size_t>(slot * c + 4)];
  p.s = saved[static_cast<size_t>(slot * c + 5)];
  p.u = Eigen::Map<const Vector>(&U[static_cast<size_t>(slot * n)], n);
  p.tu = Eigen::Map<const Vector>(&T[static_cast<size_t>(slot * n)], n);
  return p;
}

namespace {
// The rows of m whose first column (a table row) is at most `row`; m is ordered by that column.
Eigen::MatrixXd rows_up_to(const Eigen::MatrixXd& m, int row) {
  long n = 0;
  while (n < m.rows() && m(n, 0) <= row) ++n;
  return m.topRows(n);
}
}  // namespace

BranchSeed read_branch_seed(const std::string& path) {
  H5File f(path, H5File::Mode::Read);
  if (!f.exists("/branch/table")) throw std::runtime_error("'" + path + "' is not a branch file");
  BranchSeed seed;
  seed.columns = split_names(f.read_string_attribute("/branch", "columns"));
  const Eigen::MatrixXd table = read_table_rows(f, "/branch/table"), saved = read_table_rows(f, "/branch/saved");
  const Eigen::MatrixXd solutions = read_table_rows(f, "/branch/solutions"),
                        tangents = read_table_rows(f, "/branch/tangents");
  // a killed writer may have stored a solution whose table row never came, or half of a pair
  const long usable = std::min({saved.rows(), solutions.rows(), tangents.rows()});
  long slots = 0;
  while (slots < usable && saved(slots, 0) < static_cast<double>(table.rows())) ++slots;
  if (slots == 0) throw std::runtime_error("'" + path + "' holds no stored solution to continue from");
  seed.row = static_cast<int>(saved(slots - 1, 0));
  seed.table = table.topRows(seed.row + 1);
  seed.saved = saved.topRows(slots);
  seed.solutions = solutions.topRows(slots);
  seed.tangents = tangents.topRows(slots);
  seed.events = rows_up_to(read_table_rows(f, "/branch/events"), seed.row);
  seed.normal_forms = rows_up_to(read_table_rows(f, "/branch/normal_forms"), seed.row);
  const Eigen::MatrixXd modes = read_table_rows(f, "/branch/eigenvector_rows"),
                        vectors = read_table_rows(f, "/branch/eigenvectors");
  long m = rows_up_to(modes, seed.row).rows();
  m = std::min(m, vectors.rows() / 2);
  seed.eigenvector_rows = modes.topRows(m);
  seed.eigenvectors = vectors.topRows(2 * m);
  return seed;
}

std::optional<StoredMode> read_branch_mode(const std::string& path, int row) {
  H5File f(path, H5File::Mode::Read);
  const Eigen::MatrixXd rows = read_table_rows(f, "/branch/eigenvector_rows"),
                        vectors = read_table_rows(f, "/branch/eigenvectors");
  for (long k = 0; k < rows.rows() && 2 * k + 1 < vectors.rows(); ++k)
    if (static_cast<int>(rows(k, 0)) == row) {
      StoredMode m;
      m.re = vectors.row(2 * k).transpose();
      m.im = vectors.row(2 * k + 1).transpose();
      m.sigma_re = rows(k, 2);
      m.sigma_im = rows(k, 3);
      return m;
    }
  return std::nullopt;
}

bool write_branch_fields(const std::string& branch_path, const std::string& fields_path, const std::string& xdmf_path,
                         const std::string& h5_name,
                         const std::function<SolutionFields(const Vector& u, double lambda)>& fields,
                         const std::function<bool()>& stop) {
  H5File f(branch_path, H5File::Mode::Read);
  long r = 0, c = 0, n = 0, sol = 0;
  const auto saved = f.read_matrix("/branch/saved", &r, &c);
  const auto U = f.read_matrix("/branch/solutions", &sol, &n);
  const std::string parameter = f.read_string_attribute("/branch", "parameter");
  f.close();
  return write_state_fields(
      fields_path, same_file(fields_path, branch_path), std::min(r, sol),
      [&](long i) {
        const long row = static_cast<long>(saved[static_cast<size_t>(i * c)]);
        const double lambda = saved[static_cast<size_t>(i * c + 2)];
        // time = table row: the parameter need not be monotone along a branch with folds
        return StoredState{Eigen::Map<const Vector>(&U[static_cast<size_t>(i * n)], n),
                           fmt::format("/branch/fields/{}", i),
                           fmt::format("row {} ({} = {:.6g})", row, parameter, lambda),
                           static_cast<double>(row),
                           "row",
                           row,
                           parameter,
                           lambda};
      },
      [&](const StoredState& s) { return fields(s.u, s.value); }, xdmf_path, h5_name, stop);
}

}  // namespace keller

namespace keller {

namespace {
// (b - a) / eps field by field (a and b have the same layout): the linear part of the fields along
// a direction, on a's mesh
SolutionFields field_difference(const SolutionFields& a, const SolutionFields& b, double eps) {
  SolutionFields d = a;
  d.arrays.clear();
  for (size_t i = 0; i < d.nodal.size() && i < b.nodal.size(); ++i)
    d.nodal[i].values = (b.nodal[i].values - a.nodal[i].values) / eps;
  for (size_t i = 0; i < d.element.size() && i < b.element.size(); ++i) {
    d.element[i].coefficients = (b.element[i].coefficients - a.element[i].coefficients) / eps;
    d.element[i].centre_values = (b.element[i].centre_values - a.element[i].centre_values) / eps;
  }
  return d;
}
}  // namespace

std::vector<std::string> write_branch_modes(const std::string& branch_path, const std::string& h5_name,
                                            const std::string& xdmf_prefix, const std::string& suffix,
                                            const std::function<SolutionFields(const Vector& u, double lambda)>& fields,
                                            const std::function<bool()>& stop) {
  std::vector<std::string> written;
  H5File f(branch_path, H5File::Mode::Read);
  if (!f.exists("/branch/eigenvectors")) return written;
  long r = 0, c = 0, n = 0, sol = 0, er = 0, ec = 0, vr = 0, vn = 0;
  const auto saved = f.read_matrix("/branch/saved", &r, &c);
  const auto U = f.read_matrix("/branch/solutions", &sol, &n);
  const auto rows = f.read_matrix("/branch/eigenvector_rows", &er, &ec);
  const auto V = f.read_matrix("/branch/eigenvectors", &vr, &vn);
  f.close();
  H5File out(branch_path, H5File::Mode::ReadWrite);
  for (long k = 0; k < er && 2 * k + 1 < vr; ++k) {
    if (stop && stop()) return {};
    const int row = static_cast<int>(rows[static_cast<size_t>(k * ec)]);
    long slot = -1;
    for (long i = 0; i < std::min(r, sol); ++i)
      if (static_cast<int>(saved[static_cast<size_t>(i * c)]) == row) slot = i;
    if (slot < 0) continue;
    const double lambda = saved[static_cast<size_t>(slot * c + 2)];
    const Vector u = Eigen::Map<const Vector>(&U[static_cast<size_t>(slot * n)], n);
    const std::string group = fmt::format("/branch/modes/{}", k);
    if (out.exists(group)) continue;
    std::vector<XdmfSolution> steps;
    SolutionFields base;
    for (int part = 0; part < 2; ++part) {
      const Vector phi = Eigen::Map<const Vector>(&V[static_cast<size_t>((2 * k + part) * vn)], vn);
      const double pmax = phi.lpNorm<Eigen::Infinity>();
      if (!(pmax > 0)) continue;
      const double eps = 1e-7 * std::max(1.0, u.lpNorm<Eigen::Infinity>()) / pmax;
      const SolutionFields moved = fields(u + eps * phi, lambda);
      base = fields(u, lambda);  // last: problems may keep one deformed mesh for both
      const std::string g = group + (part == 0 ? "/re" : "/im");
      write_fields(out, g, field_difference(base, moved, eps));
      steps.push_back({g.substr(1), fmt::format("row {} mode, {} part", row, part == 0 ? "real" : "imaginary"),
                       static_cast<double>(part)});
    }
    if (steps.empty() || !base.mesh) continue;
    write_mesh(out, group + "/mesh", *base.mesh);
    out.set_attribute(group, "row", static_cast<long>(row));
    out.set_attribute(group, "sigma_re", rows[static_cast<size_t>(k * ec + 2)]);
    out.set_attribute(group, "sigma_im", rows[static_cast<size_t>(k * ec + 3)]);
    out.flush();
    written.push_back(fmt::format("{}_mode{}.xdmf{}", xdmf_prefix, k, suffix));
    write_xdmf(written.back(), h5_name, (group + "/mesh").substr(1), *base.mesh, steps, base);
  }
  out.close();
  return written;
}

}  // namespace keller
