// Helpers shared by the tests: finite-difference Jacobian checks with a reported maximum
// relative error, mesh distortion that keeps elements bilinear, running the keller binary.
#pragma once

#include <functional>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "continuation/output/BranchFile.hpp"
#include "core/Mesh.hpp"
#include "core/Problem.hpp"
#include "core/Term.hpp"
#include "problems/channel/ChannelMesh.hpp"

namespace keller::test {

struct JacobianCheck {
  double max_relative_error = 0;  // max |J - J_fd| / (|J_fd|_max of that row + tiny)
  int worst_row = -1, worst_col = -1;
};

// Central differences of a local term item against its Jacobian. Relative errors are taken
// against the largest entry of each row, so rounding in tiny entries does not dominate.
JacobianCheck check_term_jacobian(const Term& term, int item, const std::vector<double>& u, double h = 1e-6);
// The same for a whole problem, and for dF/dp.
JacobianCheck check_problem_jacobian(Problem& problem, const Vector& u, double h = 1e-7);
double check_parameter_derivative(Problem& problem, int p, const Vector& u, double h = 1e-6);

// Moves interior vertex nodes randomly by up to `amplitude` times the local element size
// (vertices on straight boundaries slide along them), then puts mid-side and centre nodes at
// the bilinear positions, so every element stays a general (non-parallelogram) bilinear quad.
void distort_bilinear(Mesh& mesh, double amplitude, unsigned seed);

// A custom channel mesh with these fluid columns upstream, on the deformable section and downstream,
// fluid rows and solid rows (the coarse meshes of the collapsible-channel tests).
ChannelMeshSpec custom_channel_mesh(int upstream, int deformable, int downstream, int fluid_rows, int solid_rows);

struct CommandResult {
  int exit_code = -1;
  std::string out, err;
};
// Runs the keller binary with the given arguments (a shell word list), with `env` (shell
// assignments, "A=1 B=2") in its environment. exit_code is -1 when a signal ended it.
CommandResult run_keller(const std::string& args, const std::string& env = "");
std::string source_path(const std::string& relative);
// The shell words that run the configured Python with the build's keller package on its path
// ("PYTHONPATH='BUILD/python' /usr/bin/python3"), and those that run a module of the package
// (python_module("keller.plot branch") runs `python3 -m keller.plot branch`).
std::string python_command();
std::string python_module(const std::string& module);
// The whole of a file as bytes ("" where it cannot be read).
std::string file_contents(const std::string& path);
// A fresh empty directory for a test's files.
std::string scratch_dir(const std::string& name);
// A CSV file with a header line (a study's collected table) as rows of named cells.
std::vector<std::map<std::string, std::string>> read_table(const std::string& csv);
// The rows of a stored branch table whose kind is k.
std::vector<long> rows_of_kind(const BranchTable& t, PointKind k);

}  // namespace keller::test
