// The time-series file of a run of the time integrator: one HDF5 file, written step by step in
// HDF5's single-writer/multiple-reader mode and flushed after every accepted step, so that a run
// killed at any moment (SIGKILL included) leaves a readable file holding every completed step and
// the states a restart continues from.
//
//   /evolve/table          one row per accepted step: columns in the attribute `columns`
//   /evolve/history        a ring of the last 4 states (step k in row k mod 4), rewritten in place:
//                          BDF2 continues from the last three; /evolve/history_index: step, t of each
//   /evolve/solutions      states stored every `save_every` steps (and the start and the end),
//                          /evolve/saved their step and t
//   /evolve/status         "running" while running, then why the run ended
//   /evolve/exit_code      -1, then the exit code of a run whose file takes its name
// A state is written (and flushed) before its table row, so every row's state is on disk.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "continuation/output/RunFile.hpp"
#include "continuation/time/TimeIntegrator.hpp"
#include "core/H5File.hpp"

namespace keller {

// Extra columns of the table computed from a state (the deviation from a reference state, the
// components along a perturbation's mode), with their names.
struct TimeColumns {
  std::vector<std::string> names;
  std::function<std::vector<double>(const Vector& u)> values;
};

// What a new file takes over from an unfinished one whose run it continues: its rows up to the
// last step whose state is in the ring, the stored solutions up to it, and the integrator's history.
struct TimeSeed {
  std::vector<std::string> columns;
  Eigen::MatrixXd table, saved, solutions;
  TimeHistory history;
  int step() const { return history.back.empty() ? -1 : history.back.front().step; }
};
// Reads the seed of an unfinished time-series file (also one whose writer was killed). A run killed
// inside its start (one of the two half steps written) continues from step 0. Throws
// std::runtime_error when the file holds no state to continue from.
TimeSeed read_time_seed(const std::string& path);

class TimeSeriesFile final : public TimeObserver {
 public:
  // Creates the file (a RunFile: as PATH.part, renamed to `path` once in SWMR mode), lets `header`
  // write what precedes the series (scene, mesh, the reference state), creates the datasets, writes
  // the seed of an unfinished run if given. Throws IoError on I/O errors (nothing left behind).
  TimeSeriesFile(const std::string& path, Problem& problem, TimeColumns extra, int save_every,
                 const std::function<void(H5File&)>& header, const TimeSeed* seed = nullptr);

  void on_step(const TimePoint& point) override;
  void on_finish(const std::string& reason, const TimePoint& last) override;
  // The run has ended (on_finish said why): /evolve/status gets why and, for a file that takes its
  // name, /evolve/exit_code the code the run ends with (-1 until then), in one flush, and the file
  // is closed; as BranchFile::finish.
  void finish(std::optional<int> publication_code) { run_.finish(publication_code); }
  // The file this run created, held: what it publishes must be this file.
  HeldFile& written() { return run_.written(); }

 private:
  void store(const TimePoint& p);
  void write_seed(H5File& f, const TimeSeed& seed);
  void write_history(H5File& f, int step, double t, const Vector& u);
  Problem& problem_;
  TimeColumns extra_;
  int save_every_;
  std::vector<std::string> columns_;
  int n_ = 0, saved_ = 0, last_saved_step_ = -1;
  RunFile run_;  // last: creating it writes the seed, which sets the members above
};

// The table of a time-series file (also one whose writer was killed).
struct TimeTable {
  std::vector<std::string> columns, observables;
  Eigen::MatrixXd rows;  // steps x columns
  std::string status;
  int column(const std::string& name) const;  // throws std::invalid_argument if absent
};
TimeTable read_time_table(const std::string& path);

// Writes the fields of every stored state of the time-series file `series_path` into
// /evolve/fields/<slot> of `fields_path` (the series file itself, opened for writing, when the two
// are the same; otherwise a new file) and an XDMF temporal collection (time = t) at xdmf_path
// naming the HDF5 file `h5_name`. `stop` is asked before each state: true stops it (returns false).
bool write_time_fields(const std::string& series_path, const std::string& fields_path, const std::string& xdmf_path,
                       const std::string& h5_name, const std::function<SolutionFields(const Vector& u)>& fields,
                       const std::function<bool()>& stop = {});

}  // namespace keller
