// The branch file: one HDF5 file per traced branch, written point by point in HDF5's
// single-writer/multiple-reader mode and flushed after every accepted point, so that a run
// killed at any moment (even by SIGKILL) leaves a readable file holding every completed point.
//
//   /branch/table       one row per point: columns in the attribute `columns`
//   /branch/saved       one row per stored solution: row, kind, parameter, tangent parameter
//                       part, next step, arclength
//   /branch/solutions   the stored solutions (one row each), /branch/tangents their tangents
//   /branch/events      located points that are not regular: row, kind, parameter, monitor
//   /branch/normal_forms the normal forms of located folds, branch points and Hopf points (and of
//                       a curve's cusps, Bogdanov-Takens and fold-Hopf points): row,
//                       kind, then normal_form_columns() (attribute `columns`; `types` names the
//                       type codes)
//   /branch/status      "running" while running, then why the branch ended
//   /branch/exit_code   -1, then the exit code of a run whose ended branch takes its name
// Attributes of /branch: parameter, observables, monitors, kinds, state_scale, theta.
// A file whose writer was killed opens read-only in SWMR mode (H5File does this; h5py:
// h5py.File(path, "r", swmr=True)).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "continuation/Continuation.hpp"
#include "continuation/output/RunFile.hpp"
#include "core/H5File.hpp"

namespace keller {

// What a new branch file takes over from an unfinished one when a run continues it: every row
// up to and including `row` (the last one with a stored solution), with the solutions, events
// and eigenvectors that belong to those rows.
struct BranchSeed {
  int row = -1;  // the row the run continues from: it becomes the new run's start
  std::vector<std::string> columns;
  Eigen::MatrixXd table, saved, events, eigenvector_rows, normal_forms;  // rows of those datasets, row <= `row`
  Eigen::MatrixXd solutions, tangents, eigenvectors;                     // one stored vector per row
};
// Reads the seed of an unfinished branch file (also one whose writer was killed): its rows up to
// the last one that has both its table row and its stored solution. Throws std::runtime_error
// if there is none.
BranchSeed read_branch_seed(const std::string& path);

// The numbers of a normal form (BranchPoint::normal_form; stability/NormalForms.hpp says what
// each is): type (a code of normal_form_types()), exact (1: exact derivatives, 0: differences),
// a, b, c, curvature, cubic, growth_rate_derivative, omega, period, l1, c1_re, c1_im,
// amplitude_coefficient, amplitude_entry, side, seconds, then amplitude:NAME for each observable
// (a Hopf point's orbit amplitude of it per sqrt(|lambda - lambda0|)).
std::vector<std::string> normal_form_columns(const std::vector<std::string>& observables);
// The type codes: 0 fold, 1 transcritical, 2 pitchfork (supercritical), 3 pitchfork
// (subcritical), 4 isolated point, 5 Hopf (supercritical), 6 Hopf (subcritical), 7 cusp, 8
// Bogdanov-Takens, 9 fold-Hopf.
const std::vector<std::string>& normal_form_types();

// The columns of a branch table: row, kind, s, the parameter, the observables, monitor:NAME for
// each monitor, the analysis's columns, then iterations, step, seconds, det_sign,
// tangent_parameter, saved_slot.
std::vector<std::string> branch_table_columns(const std::string& parameter, const std::vector<std::string>& observables,
                                              const std::vector<std::string>& monitors,
                                              const std::vector<std::string>& analysis);

class BranchFile final : public BranchObserver {
 public:
  // Creates the file (a RunFile: as PATH.part, renamed to `path` once in SWMR mode), lets `header`
  // write what precedes the branch (scene, mesh) and creates the branch datasets. Throws IoError on
  // I/O errors (nothing left behind).
  // analysis_columns: those of the run's PointAnalysis (after the monitors in the table); the
  // critical eigenvector of every stored solution and located fold, branch point and Hopf point goes to
  // /branch/eigenvectors (real and imaginary part, one row each; /branch/eigenvector_rows: row,
  // kind, Re sigma, Im sigma of the critical eigenvalue there).
  // seed: the rows of an unfinished run that this one continues, written first (the run's
  // points then come numbered from the seed's last row on: see ContinuedBranch).
  BranchFile(const std::string& path, const Problem& problem, const ContinuationOptions& options,
             const std::vector<std::string>& monitor_names, double state_scale,
             const std::function<void(H5File&)>& header, const std::vector<std::string>& analysis_columns = {},
             const BranchSeed* seed = nullptr);

  void on_point(const BranchPoint& point) override;
  void on_finish(const std::string& reason, const BranchPoint& last) override;
  // The file this run created, held: what it publishes must be this file.
  HeldFile& written() { return run_.written(); }
  // The run has ended (on_finish said why, and stored its last point): /branch/status gets why and,
  // for a branch that takes its name, /branch/exit_code the code its run ends with (-1 until then),
  // in one flush, and the file is closed. A run killed before it is continued by the same command
  // from its last point (which ends it at once), one killed after it published by it; never is an
  // ended branch left without its code, which would be taken for one that is not to be published.
  void finish(std::optional<int> publication_code) { run_.finish(publication_code); }

 private:
  void save_solution(const BranchPoint& p);
  void save_mode(const BranchPoint& p);
  void write_seed(H5File& f, const BranchSeed& seed);
  int n_ = 0;
  std::vector<std::string> columns_;
  std::vector<std::string> monitors_;  // the names an event's monitor index refers to
  size_t n_analysis_ = 0;
  size_t n_normal_form_ = 0;  // columns of /branch/normal_forms after row and kind
  int saved_ = 0;
  int last_saved_row_ = -1;
  int last_mode_row_ = -1;
  RunFile run_;  // last: creating it writes the seed, which sets the members above
};

// A located point of a branch file (/branch/events): every point that is neither regular nor
// the start, with the monitor whose zero it is (an event, or an end where a monitor's threshold
// ended the branch: "min_m1 < stop_below"), by name; empty where the record names none.
struct BranchEvent {
  int row = -1;
  PointKind kind = PointKind::Regular;
  double parameter = 0.0;
  std::string monitor;
};

// Reading a branch file (also one whose writer was killed).
struct BranchTable {
  std::string parameter;
  std::vector<std::string> columns;
  std::vector<std::string> observables, monitors;
  Eigen::MatrixXd rows;  // points x columns
  std::string status;
  double state_scale = 1.0, theta = 0.5;
  std::vector<int> saved_rows;                // table rows with stored solutions, in storage order
  std::vector<BranchEvent> events;            // the located points, in the order they were written
  int column(const std::string& name) const;  // throws if absent
  // The monitor whose zero the located row `row` is (BranchEvent::monitor); empty if none.
  std::string located_monitor(int row) const;
};
BranchTable read_branch_table(const std::string& path);
// A stored point (solution, tangent, step, arclength). Throws std::invalid_argument listing the
// stored rows if `row` has no stored solution; row = -1 means the last stored one.
BranchPoint read_branch_point(const std::string& path, int row);
// The critical eigenvector stored with a row of a branch file (/branch/eigenvectors): phi = re + i im
// with its eigenvalue sigma (at a Hopf point, sigma_im is its frequency). Nothing when the row has
// none (no [stability], or neither a stored row nor a located fold, branch point or Hopf point).
struct StoredMode {
  Vector re, im;
  double sigma_re = 0.0, sigma_im = 0.0;
};
std::optional<StoredMode> read_branch_mode(const std::string& path, int row);

// Writes the fields of every stored solution into /branch/fields/<slot> of `fields_path` (the
// branch file itself, opened for writing, when the two paths are equal; otherwise a new file)
// and an XDMF temporal collection (one step per stored solution, time = table row) at
// xdmf_path, which names the HDF5 file `h5_name` (its final name beside the XDMF file).
// `fields` turns a stored solution (at the stored parameter value) into fields. `stop` is asked
// before each solution: when it answers true, nothing more is written and false is returned.
bool write_branch_fields(const std::string& branch_path, const std::string& fields_path, const std::string& xdmf_path,
                         const std::string& h5_name,
                         const std::function<SolutionFields(const Vector& u, double lambda)>& fields,
                         const std::function<bool()>& stop = {});

// The critical eigenvectors stored with located folds, branch points and Hopf points, as fields
// (real and imaginary part: the linear change of the fields along the eigenvector, on the
// mesh of the state; a displacement mode for moving meshes) in /branch/modes/<k> of the branch
// file (opened for writing), and one XDMF file per mode at <xdmf_prefix>_mode<k>.xdmf<suffix>
// naming the HDF5 file `h5_name`. Returns the XDMF paths written (none when `stop` stopped it).
std::vector<std::string> write_branch_modes(const std::string& branch_path, const std::string& h5_name,
                                            const std::string& xdmf_prefix, const std::string& suffix,
                                            const std::function<SolutionFields(const Vector& u, double lambda)>& fields,
                                            const std::function<bool()>& stop = {});

}  // namespace keller
