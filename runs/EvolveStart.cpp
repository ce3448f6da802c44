#include "runs/EvolveStart.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "continuation/orbits/OrbitMeasures.hpp"
#include "continuation/output/TimeSeriesFile.hpp"
#include "core/H5File.hpp"
#include "runs/OutputFile.hpp"
#include "runs/SceneLoader.hpp"
#include "runs/StoredStart.hpp"

namespace keller {

bool is_time_series(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  try {
    H5File f(path, H5File::Mode::Read);
    return f.exists("/evolve");
  } catch (const std::exception&) {
    return false;
  }
}

EvolveStart read_evolve_start(const std::string& path, const LoadedScene& scene, Problem& problem,
                              const std::string& parameter, bool force, std::vector<std::string>& warnings) {
  const std::string where = fmt::format("--from '{}'", path);
  RunHeader header;
  {
    H5File f(path, H5File::Mode::Read);
    header = read_run_header(f);
  }
  std::vector<std::string> refusals = origin_refusals(header, scene, problem);
  for (const Parameter& p : problem.parameters().list()) {
    const auto it = header.parameters.find(p.name);
    if (p.name == parameter || it == header.parameters.end()) continue;
    if (std::abs(it->second - p.value) > 1e-12 * std::max({1.0, std::abs(it->second), std::abs(p.value)}))
      refusals.push_back(
          fmt::format("it was integrated at {} = {}, this scene sets {} = {}", p.name, it->second, p.name, p.value));
  }
  refuse_unless_forced(refusals, where, force, warnings);
  EvolveStart out;
  const auto value = header.parameters.find(parameter);
  out.parameter = value != header.parameters.end() ? value->second
                                                   : problem.parameters().value(problem.parameters().index(parameter));
  TimeSeed seed;
  try {
    seed = read_time_seed(path);
  } catch (const std::runtime_error& e) {
    throw std::invalid_argument(fmt::format("{}: {}", where, e.what()));
  }
  if (seed.history.back.empty()) throw std::invalid_argument(where + ": the run holds no state");
  out.u = seed.history.back.front().u;
  out.t = seed.history.back.front().t;
  if (out.u.size() != problem.size())
    throw std::invalid_argument(
        fmt::format("{}: its states have {} unknowns, this scene's problem {}", where, out.u.size(), problem.size()));
  const auto column = [&](const std::string& name) {
    const auto it = std::find(seed.columns.begin(), seed.columns.end(), name);
    return it == seed.columns.end() ? -1 : static_cast<int>(it - seed.columns.begin());
  };
  const int c_t = column("t");
  if (c_t < 0) throw std::invalid_argument(where + ": its time table has no column 't'");
  std::vector<double> t(static_cast<size_t>(seed.table.rows()));
  for (long r = 0; r < seed.table.rows(); ++r) t[static_cast<size_t>(r)] = seed.table(r, c_t);
  double swing = 0.0;
  for (const std::string& name : problem.observable_names()) {
    const int c = column(name);
    if (c < 0) continue;
    std::vector<double> y(t.size());
    double lo = INFINITY, hi = -INFINITY, size = 0.0;
    for (size_t r = 0; r < t.size(); ++r) {
      y[r] = seed.table(static_cast<long>(r), c);
      if (t[r] < 0.5 * (t.front() + t.back())) continue;
      lo = std::min(lo, y[r]);
      hi = std::max(hi, y[r]);
      size = std::max(size, std::abs(y[r]));
    }
    const double relative = size > 0.0 ? (hi - lo) / size : 0.0;
    if (!(relative > swing)) continue;
    if (const std::optional<double> T = oscillation_period(t, y)) {
      swing = relative;
      out.period = *T;
      out.observable = name;
    }
  }
  if (out.observable.empty())
    throw std::invalid_argument(
        fmt::format("{}: no observable oscillates through three periods in the second half of the run (t = {} to {}): "
                    "integrate longer, or where the steady state is unstable",
                    where, t.empty() ? 0.0 : t.front(), t.empty() ? 0.0 : t.back()));
  return out;
}

}  // namespace keller
