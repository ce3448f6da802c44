// What the run files of the engines (branch files, time series) share beside their RunFile: a list
// of names stored as one comma-separated attribute, 2D datasets read into and appended from Eigen
// matrices, columns found by name, and the fields of their stored states with an XDMF file.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/H5File.hpp"
#include "core/SolutionFields.hpp"
#include "core/Types.hpp"

namespace keller {

// "a,b,c" from {a, b, c}, and back (an empty text: no names).
std::string join_names(const std::vector<std::string>& names);
std::vector<std::string> split_names(const std::string& text);

// The rows of a 2D dataset (an empty matrix where it does not exist).
Eigen::MatrixXd read_table_rows(const H5File& file, const std::string& dataset);
// Appends the rows of m to an appendable dataset (nothing for an empty m).
void append_table_rows(H5File& file, const std::string& dataset, const Eigen::MatrixXd& m);
// The index of the column `name`; throws std::invalid_argument ("<table> has no column 'name'").
int column_index(const std::vector<std::string>& columns, const std::string& name, const std::string& table);
// Refuses the seed of an unfinished run (`what`: "branch", "run") that a run with these columns
// and `n` unknowns cannot continue: other columns, or stored states of another size. Throws
// std::runtime_error.
void check_seed(const std::string& what, const std::vector<std::string>& seed_columns,
                const std::vector<std::string>& columns, const Eigen::MatrixXd& states, long n);

// A stored state of a run file: where its fields go, what its XDMF step says and its time, and
// two attributes of the group (the row or step it belongs to, and the parameter or time there).
struct StoredState {
  Vector u;
  std::string group, label;
  double time = 0.0;
  std::string index_name;
  long index = 0;
  std::string value_name;
  double value = 0.0;
};

// Writes the fields (`fields` of each state) of `count` stored states (`state`) into their groups
// of the file at `fields_path` (opened for writing when `in_place`, else created), keeping groups
// an earlier run of this wrote, with the mesh in /mesh, and an XDMF temporal collection of them at
// xdmf_path naming the HDF5 file `h5_name`. `stop` is asked before each state: true stops it.
bool write_state_fields(const std::string& fields_path, bool in_place, long count,
                        const std::function<StoredState(long slot)>& state,
                        const std::function<SolutionFields(const StoredState&)>& fields, const std::string& xdmf_path,
                        const std::string& h5_name, const std::function<bool()>& stop);

}  // namespace keller
