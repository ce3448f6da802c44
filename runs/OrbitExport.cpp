#include "runs/OrbitExport.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "continuation/orbits/OrbitContinuation.hpp"
#include "continuation/output/BranchFile.hpp"
#include "continuation/output/TableRows.hpp"
#include "core/H5File.hpp"
#include "core/PendingFile.hpp"
#include "runs/ExitCode.hpp"
#include "runs/Interrupts.hpp"
#include "runs/OutputFile.hpp"
#include "runs/PointLabels.hpp"
#include "runs/SceneLoader.hpp"
#include "runs/TraceCommand.hpp"
#include "runs/TraceStart.hpp"

namespace keller {

namespace fs = std::filesystem;

std::string orbit_export_path(const std::string& input, const std::string& row) {
  const fs::path p(input);
  return (p.parent_path() / (p.stem().string() + "-orbit" + row + ".h5")).string();
}

int export_orbit(const std::string& input, const std::string& row_text, int frames) {
  const BranchTable table = read_branch_table(input);
  if (std::find(table.columns.begin(), table.columns.end(), "period") == table.columns.end())
    throw std::invalid_argument(
        fmt::format("'{}' is not an orbit branch (keller trace --orbit): no column 'period'", input));
  int row = -1;
  const char* end = row_text.data() + row_text.size();
  const auto [at, error] = std::from_chars(row_text.data(), end, row);
  if (row_text.empty() || error != std::errc() || at != end)  // not a number: a label
    row = row_of_label(table, row_text, "'" + input + "'");
  if (std::find(table.saved_rows.begin(), table.saved_rows.end(), row) == table.saved_rows.end())
    throw std::invalid_argument(fmt::format("'{}': row {} holds no stored orbit", input, row_text));
  std::string scene_text;
  RunHeader header;
  {
    H5File f(input, H5File::Mode::Read);
    scene_text = f.read_string("/scene");
    header = read_run_header(f);
  }
  const LoadedScene loaded = load_scene_text(scene_text, input + ":/scene", declare_trace_keys);
  auto problem = loaded.type->build(loaded.scene);
  for (const auto& [name, value] : header.parameters)
    if (problem->parameters().has(name)) problem->parameters().set(name, value);
  const BranchPoint point = read_branch_point(input, row);
  problem->parameters().set(table.parameter, point.lambda);
  const double T = table.rows(row, table.column("period"));
  const TraceSettings settings = TraceSettings::from_scene(loaded.scene);
  const OrbitContinuationOptions options = OrbitContinuationOptions::from_scene(loaded.scene, settings.continuation);
  if (frames <= 0) frames = options.frames;
  // the adaptive run's steps with the frame times added: every frame an integrator state
  const ShootingOptions shooting;
  const OrbitGrid grid = record_grid(*problem, point.u, T, options.time, shooting.newton, shooting.lu);
  std::vector<double> times;
  for (double f : grid.fractions) times.push_back(f * T);
  for (int k = 1; k < frames; ++k) times.push_back(T * k / frames);
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end(), [&](double a, double b) { return b - a < 1e-12 * T; }),
              times.end());
  class Frames final : public TimeObserver {
   public:
    Frames(double period, int count) : period_(period), count_(count) {}
    void on_step(const TimePoint& p) override {
      const double k = p.t / period_ * count_;
      if (std::abs(k - std::round(k)) < 1e-9 * count_) states.emplace_back(p.t, p.u);
    }
    std::vector<std::pair<double, Vector>> states;

   private:
    double period_;
    int count_;
  } frames_of(T, frames);  // the start (t = 0) too: run_on_grid reports it
  TimeOptions o = options.time;
  o.t_end = T;
  const TimeResult r =
      TimeIntegrator(*problem, o, shooting.newton, shooting.lu).run_on_grid(point.u, 0.0, times, frames_of);
  if (r.code != TimeStop::End)
    throw std::runtime_error(
        fmt::format("'{}': row {}: the orbit's integration failed: {}", input, row_text, r.reason));
  const std::string out = orbit_export_path(input, row_text);
  const std::string xdmf = xdmf_path_for(out);
  PendingFile fields(out);
  const bool complete = write_state_fields(
      fields.path(), false, static_cast<long>(frames_of.states.size()),
      [&](long i) {
        const auto& [t, u] = frames_of.states[static_cast<size_t>(i)];
        return StoredState{
            u, fmt::format("/orbit/fields/{}", i), fmt::format("t = {:.6g} of T = {:.6g}", t, T), t, "frame", i, "t",
            t};
      },
      [&](const StoredState& s) { return problem->fields(s.u); }, xdmf + ".pending", fs::path(out).filename().string(),
      &InterruptGuard::requested);
  if (!complete) {
    fmt::print("interrupted: nothing written\n");
    return exit_code::interrupted;
  }
  fields.commit();
  const bool animated = fs::exists(xdmf + ".pending");  // a problem without a mesh has no XDMF
  if (animated) fs::rename(xdmf + ".pending", xdmf);
  fmt::print("wrote the orbit of row {} ({} = {:.10g}, T = {:.10g}) in {} frames to {}{}\n", row_text, table.parameter,
             point.lambda, T, frames_of.states.size(), out, animated ? " and " + xdmf : "");
  return exit_code::ok;
}

}  // namespace keller
