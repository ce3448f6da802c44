// The branch file: one HDF5 file per traced branch, written point by point in HDF5's
// single-writer/multiple-reader mode and flushed after every accepted point, so that a run
// killed at any moment (even by SIGKILL) leaves a readable file holding every completed point.
//
//   /branch/table       one row per point: columns in the attribute `columns`
//   /branch/saved       one row per stored solution: row, kind, parameter, tangent parameter
//                       part, next step, arclength
//   /branch/solutions   the stored solutions (one row each), /branch/tangents their tangents
//   /branch/events      located points that are not regular: row, kind, parameter, monitor
//   /branch/status      "running" while running, then why the branch ended
// Attributes of /branch: parameter, observables, monitors, kinds, state_scale, theta.
// A file whose writer was killed opens read-only in SWMR mode (H5File does this; h5py:
// h5py.File(path, "r", swmr=True)).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "continuation/Continuation.hpp"
#include "core/H5File.hpp"

namespace keller {

class BranchFile final : public BranchObserver {
 public:
  // Creates `path` (replacing it), lets `header` write what precedes the branch (scene, mesh),
  // creates the branch datasets and enters SWMR mode; the file appears under `path` only then.
  // Throws std::runtime_error on I/O errors.
  // analysis_columns: those of the run's PointAnalysis (after the monitors in the table); the
  // critical eigenvector of every stored solution and located fold, branch point and Hopf point goes to
  // /branch/eigenvectors (real and imaginary part, one row each; /branch/eigenvector_rows: row,
  // kind, Re sigma, Im sigma of the critical eigenvalue there).
  BranchFile(const std::string& path, const Problem& problem, const ContinuationOptions& options,
             const std::vector<std::string>& monitor_names, double state_scale,
             const std::function<void(H5File&)>& header, const std::vector<std::string>& analysis_columns = {});
  ~BranchFile() override;

  void on_point(const BranchPoint& point) override;
  void on_finish(const std::string& reason, const BranchPoint& last) override;
  const std::string& path() const { return path_; }
  // Closes the file (on_finish does).
  void close();

 private:
  void save_solution(const BranchPoint& p);
  void save_mode(const BranchPoint& p);
  int last_mode_row_ = -1;
  std::string path_;
  std::unique_ptr<H5File> file_;
  int n_ = 0;
  int saved_ = 0;
  int last_saved_row_ = -1;
  std::vector<std::string> columns_;
  size_t n_analysis_ = 0;
};

// Reading a branch file (also one whose writer was killed).
struct BranchTable {
  std::string parameter;
  std::vector<std::string> columns;
  std::vector<std::string> observables, monitors;
  Eigen::MatrixXd rows;  // points x columns
  std::string status;
  double state_scale = 1.0, theta = 0.5;
  std::vector<int> saved_rows;  // table rows with stored solutions, in storage order
  int column(const std::string& name) const;  // throws if absent
};
BranchTable read_branch_table(const std::string& path);
// A stored point (solution, tangent, step, arclength). Throws std::invalid_argument listing the
// stored rows if `row` has no stored solution; row = -1 means the last stored one.
BranchPoint read_branch_point(const std::string& path, int row);

// Writes the fields of every stored solution into /branch/fields/<slot> of `fields_path` and an
// XDMF temporal collection (one step per stored solution, time = table row) at xdmf_path.
// `fields` turns a stored solution (at the stored parameter value) into fields.
void write_branch_fields(const std::string& branch_path, const std::string& fields_path, const std::string& xdmf_path,
                         const std::function<SolutionFields(const Vector& u, double lambda)>& fields);

// The critical eigenvectors stored with located folds, branch points and Hopf points, as fields
// (real and imaginary part: the linear change of the fields along the eigenvector, on the
// mesh of the state; a displacement mode for moving meshes) in /branch/modes/<k> of the branch
// file, and one XDMF file per mode, <xdmf_prefix>_mode<k>.xdmf. Returns the number written.
int write_branch_modes(const std::string& branch_path, const std::string& xdmf_prefix,
                       const std::function<SolutionFields(const Vector& u, double lambda)>& fields);

}  // namespace keller
