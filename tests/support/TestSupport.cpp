#include "support/TestSupport.hpp"

#include <fmt/format.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace keller::test {

JacobianCheck check_term_jacobian(const Term& term, int item, const std::vector<double>& u, double h) {
  const int n = term.local_size(), k = term.local_rows();
  std::vector<double> r(k), J(static_cast<size_t>(k) * n), rp(k), rm(k), up = u;
  term.jacobian(item, u.data(), r.data(), J.data());
  std::vector<double> fd(static_cast<size_t>(k) * n);
  for (int j = 0; j < n; ++j) {
    const double hj = h * std::max(1.0, std::abs(u[j]));
    up[j] = u[j] + hj;
    term.residual(item, up.data(), rp.data());
    up[j] = u[j] - hj;
    term.residual(item, up.data(), rm.data());
    up[j] = u[j];
    for (int i = 0; i < k; ++i) fd[static_cast<size_t>(i) * n + j] = (rp[i] - rm[i]) / (2 * hj);
  }
  JacobianCheck out;
  for (int i = 0; i < k; ++i) {
    double scale = 1e-300;
    for (int j = 0; j < n; ++j) scale = std::max(scale, std::abs(fd[static_cast<size_t>(i) * n + j]));
    for (int j = 0; j < n; ++j) {
      const double e = std::abs(J[static_cast<size_t>(i) * n + j] - fd[static_cast<size_t>(i) * n + j]) / scale;
      if (e > out.max_relative_error) out = {e, i, j};
    }
  }
  return out;
}

JacobianCheck check_problem_jacobian(Problem& problem, const Vector& u, double h) {
  Vector F, Fp, Fm;
  SparseMatrix J = problem.jacobian_pattern();
  problem.jacobian(u, F, J);
  const Eigen::MatrixXd Jd = Eigen::MatrixXd(J);
  Eigen::MatrixXd fd(u.size(), u.size());
  Vector up = u;
  for (int j = 0; j < u.size(); ++j) {
    const double hj = h * std::max(1.0, std::abs(u[j]));
    up[j] = u[j] + hj;
    problem.residual(up, Fp);
    up[j] = u[j] - hj;
    problem.residual(up, Fm);
    up[j] = u[j];
    fd.col(j) = (Fp - Fm) / (2 * hj);
  }
  JacobianCheck out;
  for (int i = 0; i < u.size(); ++i) {
    const double scale = std::max(1e-300, fd.row(i).cwiseAbs().maxCoeff());
    for (int j = 0; j < u.size(); ++j) {
      const double e = std::abs(Jd(i, j) - fd(i, j)) / scale;
      if (e > out.max_relative_error) out = {e, i, j};
    }
  }
  return out;
}

double check_parameter_derivative(Problem& problem, int p, const Vector& u, double h) {
  Vector dF, Fp, Fm;
  problem.parameter_derivative(p, u, dF);
  ParameterSet& ps = problem.parameters();
  const double v = ps.value(p), hv = h * std::max(1.0, std::abs(v));
  ps.set(p, v + hv);
  problem.residual(u, Fp);
  ps.set(p, v - hv);
  problem.residual(u, Fm);
  ps.set(p, v);
  const Vector fd = (Fp - Fm) / (2 * hv);
  const double scale = std::max(1e-300, fd.cwiseAbs().maxCoeff());
  return (dF - fd).cwiseAbs().maxCoeff() / scale;
}

void distort_bilinear(Mesh& mesh, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  // local size and boundary classification of each vertex
  std::vector<double> size(mesh.num_nodes(), 1e300);
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const auto& el = mesh.element(e);
    const double hx = std::abs(mesh.node(el[2])[0] - mesh.node(el[0])[0]);
    const double hy = std::abs(mesh.node(el[6])[1] - mesh.node(el[0])[1]);
    for (int v : ref::q1_node) size[el[v]] = std::min({size[el[v]], hx, hy});
  }
  std::vector<int> fix_x(mesh.num_nodes(), 0), fix_y(mesh.num_nodes(), 0);
  for (const std::string& b : mesh.boundary_names()) {
    for (int n : mesh.boundary_nodes(b)) {
      // a boundary of constant x or constant y: slide along it
      const auto& edges = mesh.boundary(b);
      const auto& el = mesh.element(edges[0].element);
      const auto& nodes = ref::edge_nodes[edges[0].edge];
      const bool vertical = std::abs(mesh.node(el[nodes[0]])[0] - mesh.node(el[nodes[2]])[0]) < 1e-12;
      (vertical ? fix_x : fix_y)[n] = 1;
    }
  }
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    if (!mesh.is_vertex(n)) continue;
    auto p = mesh.node(n);
    if (!fix_x[n]) p[0] += amplitude * size[n] * U(rng);
    if (!fix_y[n]) p[1] += amplitude * size[n] * U(rng);
    mesh.set_node(n, p);
  }
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const auto& el = mesh.element(e);
    const auto v0 = mesh.node(el[0]), v2 = mesh.node(el[2]), v6 = mesh.node(el[6]), v8 = mesh.node(el[8]);
    for (int a = 0; a < 9; ++a) {
      if (a == 0 || a == 2 || a == 6 || a == 8) continue;
      const double s = 0.5 * (ref::node_s(a) + 1.0), t = 0.5 * (ref::node_t(a) + 1.0);
      Mesh::Point p;
      for (int i = 0; i < 2; ++i)
        p[i] = (1 - s) * (1 - t) * v0[i] + s * (1 - t) * v2[i] + (1 - s) * t * v6[i] + s * t * v8[i];
      mesh.set_node(el[a], p);
    }
  }
}

ChannelMeshSpec custom_channel_mesh(int upstream, int deformable, int downstream, int fluid_rows, int solid_rows) {
  ChannelMeshSpec m;
  m.name = "custom";
  m.nx_upstream = upstream;
  m.nx_deformable = deformable;
  m.nx_downstream = downstream;
  m.ny_fluid = fluid_rows;
  m.ny_solid = solid_rows;
  return m;
}

CommandResult run_keller(const std::string& args, const std::string& env) {
  const std::string err_file = std::filesystem::temp_directory_path() / fmt::format("keller_err_{}.txt", ::getpid());
  // exec: the shell becomes keller, so a signal that ends keller is what pclose reports
  const std::string cmd = fmt::format("{} exec {} {} 2>{}", env, KELLER_BINARY, args, err_file);
  CommandResult res;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return res;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) res.out.append(buf.data(), n);
  const int status = ::pclose(pipe);
  res.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(err_file);
  std::stringstream ss;
  ss << in.rdbuf();
  res.err = ss.str();
  std::filesystem::remove(err_file);
  return res;
}

std::string source_path(const std::string& relative) { return std::string(KELLER_SOURCE_DIR) + "/" + relative; }

std::string python_command() { return std::string("PYTHONPATH='") + KELLER_PYTHON_PATH + "' " + KELLER_PYTHON; }

std::string python_module(const std::string& module) { return python_command() + " -m " + module; }

std::string file_contents(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string scratch_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / fmt::format("keller_test_{}_{}", name, ::getpid());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

std::vector<std::map<std::string, std::string>> read_table(const std::string& csv) {
  std::ifstream in(csv);
  std::string line;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    // RFC 4180 cells: a quoted cell may hold commas, and "" inside it is one quote
    std::vector<std::string> cells(1);
    bool quoted = false;
    for (size_t i = 0; i < line.size(); ++i) {
      const char ch = line[i];
      if (quoted && ch == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        cells.back() += '"';
        ++i;
      } else if (ch == '"') {
        quoted = !quoted;
      } else if (ch == ',' && !quoted) {
        cells.emplace_back();
      } else {
        cells.back() += ch;
      }
    }
    if (header.empty()) {
      header = cells;
      continue;
    }
    std::map<std::string, std::string> row;
    for (size_t i = 0; i < cells.size() && i < header.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

std::vector<long> rows_of_kind(const BranchTable& t, PointKind k) {
  std::vector<long> out;
  const int kind = t.column("kind");
  for (long i = 0; i < t.rows.rows(); ++i)
    if (static_cast<int>(t.rows(i, kind)) == static_cast<int>(k)) out.push_back(i);
  return out;
}

}  // namespace keller::test
