#include "continuation/output/TimeSeriesFile.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "continuation/output/TableRows.hpp"
#include "core/RunFiles.hpp"
#include "core/SignalPoint.hpp"
#include "core/SolutionWriter.hpp"

namespace keller {

namespace {

// The ring of states: BDF2 and its error estimate need the last three; a fourth row is the one
// being rewritten, so a kill in the middle of that write never touches the three a restart reads.
constexpr long kRing = 4;

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// The columns every table has, before the observables and the extra columns.
const std::vector<std::string> kLeading = {"step",           "t",        "h",         "order",  "error", "iterations",
                                           "factorisations", "rejected", "next_step", "seconds"};

int column_of(const std::vector<std::string>& columns, const std::string& name) {
  return column_index(columns, name, "the time table");
}

std::vector<std::string> time_columns(const Problem& problem, const TimeColumns& extra) {
  std::vector<std::string> columns = kLeading;
  for (const std::string& o : problem.observable_names()) columns.push_back(o);
  for (const std::string& e : extra.names) columns.push_back(e);
  columns.push_back("saved_slot");
  return columns;
}

}  // namespace

TimeSeriesFile::TimeSeriesFile(const std::string& path, Problem& problem, TimeColumns extra, int save_every,
                               const std::function<void(H5File&)>& header, const TimeSeed* seed)
    : problem_(problem),
      extra_(std::move(extra)),
      save_every_(std::max(save_every, 1)),
      columns_(time_columns(problem, extra_)),
      n_(problem.size()),
      run_(path, "/evolve", [&](H5File& f) {
        if (header) header(f);
        f.create_group("/evolve");
        f.set_attribute("/evolve", "columns", join_names(columns_));
        f.set_attribute("/evolve", "observables", join_names(problem.observable_names()));
        f.set_attribute("/evolve", "save_every", static_cast<long>(save_every_));
        f.create_appendable("/evolve/table", static_cast<long>(columns_.size()));
        f.create_appendable("/evolve/history", n_, 1);
        f.create_appendable("/evolve/history_index", 2, kRing);
        f.set_attribute("/evolve/history_index", "columns", std::string("step,t"));
        const RowMajor zeros = RowMajor::Zero(kRing, n_);
        f.append_rows("/evolve/history", zeros.data(), kRing);
        const RowMajor none = RowMajor::Constant(kRing, 2, -1.0);
        f.append_rows("/evolve/history_index", none.data(), kRing);
        f.create_appendable("/evolve/solutions", n_, 1);
        f.create_appendable("/evolve/saved", 2, 16);
        f.set_attribute("/evolve/saved", "columns", std::string("step,t"));
        if (seed) write_seed(f, *seed);
      }) {}

void TimeSeriesFile::write_seed(H5File& f, const TimeSeed& seed) {
  check_seed("run", seed.columns, columns_, seed.solutions, n_);
  append_table_rows(f, "/evolve/table", seed.table);
  append_table_rows(f, "/evolve/saved", seed.saved);
  append_table_rows(f, "/evolve/solutions", seed.solutions);
  for (auto it = seed.history.back.rbegin(); it != seed.history.back.rend(); ++it)
    write_history(f, it->step, it->t, it->u);
  saved_ = static_cast<int>(seed.saved.rows());
  if (saved_ > 0) last_saved_step_ = static_cast<int>(seed.saved(saved_ - 1, 0));
}

void TimeSeriesFile::write_history(H5File& f, int step, double t, const Vector& u) {
  const long slot = step % kRing;
  f.write_rows("/evolve/history", slot, u.data(), 1);
  const double index[2] = {static_cast<double>(step), t};
  f.write_rows("/evolve/history_index", slot, index, 1);
}

void TimeSeriesFile::store(const TimePoint& p) {
  run_.h5().append_rows("/evolve/solutions", p.u.data(), 1);
  const double row[2] = {static_cast<double>(p.step), p.t};
  run_.h5().append_rows("/evolve/saved", row, 1);
  last_saved_step_ = p.step;
  ++saved_;
}

void TimeSeriesFile::on_step(const TimePoint& p) {
  if (!run_.is_open()) return;
  write_history(run_.h5(), p.step, p.t, p.u);
  const bool save = p.step % save_every_ == 0;
  const int slot = save ? saved_ : -1;
  if (save) store(p);
  std::vector<double> row = {static_cast<double>(p.step),
                             p.t,
                             p.h,
                             static_cast<double>(p.order),
                             p.error,
                             static_cast<double>(p.iterations),
                             static_cast<double>(p.factorisations),
                             static_cast<double>(p.rejected),
                             p.next_step,
                             p.seconds};
  std::vector<double> obs;
  const size_t n_obs = problem_.observable_names().size();
  if (!problem_.observables(p.u, obs).is_ok() || obs.size() != n_obs) obs.assign(n_obs, NAN);
  row.insert(row.end(), obs.begin(), obs.end());
  if (!extra_.names.empty()) {
    const std::vector<double> e = extra_.values(p.u);
    row.insert(row.end(), e.begin(), e.end());
  }
  row.push_back(static_cast<double>(slot));
  if (row.size() != columns_.size())
    throw std::logic_error(fmt::format("time row has {} values for {} columns", row.size(), columns_.size()));
  run_.h5().append_rows("/evolve/table", row.data(), 1);
  run_.h5().flush();
  signal_point("step");
}

void TimeSeriesFile::on_finish(const std::string& reason, const TimePoint& last) {
  if (!run_.is_open()) return;
  // the last state is always stored (fields at the end of the run)
  if (last.step != last_saved_step_ && last.u.size() == n_) store(last);
  run_.ended(reason);
}

int TimeTable::column(const std::string& name) const { return column_of(columns, name); }

TimeTable read_time_table(const std::string& path) {
  H5File f(path, H5File::Mode::Read);
  if (!f.exists("/evolve/table")) throw std::runtime_error("'" + path + "' is not a time-series file (no /evolve)");
  TimeTable t;
  t.columns = split_names(f.read_string_attribute("/evolve", "columns"));
  t.observables = split_names(f.read_string_attribute("/evolve", "observables"));
  t.rows = read_table_rows(f, "/evolve/table");
  if (f.exists("/evolve/status")) t.status = f.read_string("/evolve/status");
  return t;
}

TimeSeed read_time_seed(const std::string& path) {
  H5File f(path, H5File::Mode::Read);
  if (!f.exists("/evolve/table")) throw std::runtime_error("'" + path + "' is not a time-series file");
  TimeSeed seed;
  seed.columns = split_names(f.read_string_attribute("/evolve", "columns"));
  const Eigen::MatrixXd table = read_table_rows(f, "/evolve/table");
  const Eigen::MatrixXd ring = read_table_rows(f, "/evolve/history"),
                        index = read_table_rows(f, "/evolve/history_index");
  if (table.rows() == 0) throw std::runtime_error("'" + path + "' holds no step to continue from");
  const int c_step = column_of(seed.columns, "step"), c_t = column_of(seed.columns, "t"),
            c_h = column_of(seed.columns, "h"), c_next = column_of(seed.columns, "next_step"),
            c_order = column_of(seed.columns, "order");
  long last = table.rows() - 1;
  // a start of which only the first half step was written is taken again from the beginning
  if (static_cast<int>(table(last, c_step)) == 1) last = 0;
  const int k = static_cast<int>(table(last, c_step));
  for (int step = k; step >= std::max(0, k - 2); --step) {
    const long slot = step % kRing;
    if (slot >= index.rows() || static_cast<int>(index(slot, 0)) != step)
      throw std::runtime_error(fmt::format("'{}': the state of step {} is not in its history", path, step));
    const long row = last - (k - step);
    TimePoint p;
    p.step = step;
    p.t = table(row, c_t);
    p.h = table(row, c_h);
    p.order = static_cast<int>(table(row, c_order));
    p.next_step = table(row, c_next);
    p.u = ring.row(slot).transpose();
    seed.history.back.push_back(std::move(p));
  }
  seed.history.next_step = table(last, c_next);
  seed.table = table.topRows(last + 1);
  const Eigen::MatrixXd saved = read_table_rows(f, "/evolve/saved"),
                        solutions = read_table_rows(f, "/evolve/solutions");
  long slots = 0;
  while (slots < std::min(saved.rows(), solutions.rows()) && saved(slots, 0) <= k) ++slots;
  seed.saved = saved.topRows(slots);
  seed.solutions = solutions.topRows(slots);
  // a table row's saved_slot must point at a stored state: rows whose state was not kept lose it
  const int c_slot = column_of(seed.columns, "saved_slot");
  for (long r = 0; r < seed.table.rows(); ++r)
    if (seed.table(r, c_slot) >= static_cast<double>(slots)) seed.table(r, c_slot) = -1.0;
  return seed;
}

bool write_time_fields(const std::string& series_path, const std::string& fields_path, const std::string& xdmf_path,
                       const std::string& h5_name, const std::function<SolutionFields(const Vector& u)>& fields,
                       const std::function<bool()>& stop) {
  long r = 0, c = 0, n = 0, sol = 0;
  std::vector<double> saved, U;
  {
    H5File in(series_path, H5File::Mode::Read);
    saved = in.read_matrix("/evolve/saved", &r, &c);
    U = in.read_matrix("/evolve/solutions", &sol, &n);
  }
  return write_state_fields(
      fields_path, same_file(series_path, fields_path), std::min(r, sol),
      [&](long i) {
        const long step = static_cast<long>(saved[static_cast<size_t>(i * c)]);
        const double t = saved[static_cast<size_t>(i * c + 1)];
        return StoredState{Eigen::Map<const Vector>(&U[static_cast<size_t>(i * n)], n),
                           fmt::format("/evolve/fields/{}", i),
                           fmt::format("step {} (t = {:.6g})", step, t),
                           t,
                           "step",
                           step,
                           "t",
                           t};
      },
      [&](const StoredState& s) { return fields(s.u); }, xdmf_path, h5_name, stop);
}

}  // namespace keller
