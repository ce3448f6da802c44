#include "python/src/python_problem.hpp"

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <utility>

#include "problems/ProblemRegistry.hpp"
#include "runs/CommandFailure.hpp"
#include "runs/ExitCode.hpp"

namespace py = pybind11;

namespace keller::python {

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Index = py::array_t<int, py::array::c_style | py::array::forcecast>;

std::optional<py::object> g_current;          // the problem of the running keller.* call
std::optional<py::error_already_set> g_kept;  // the first Python exception of the running command

py::array_t<double> to_numpy(const Vector& u) { return py::array_t<double>(u.size(), u.data()); }

// A sequence of n numbers from Python (a numpy array, a list) into out.
void from_numpy(const py::handle& value, int n, const char* what, Vector& out) {
  const Array a = Array::ensure(value);
  if (!a || a.ndim() != 1 || a.shape(0) != n) {
    PyErr_SetString(PyExc_ValueError, fmt::format("{}() must return {} numbers (a 1D array), got {}", what, n,
                                                  py::str(py::repr(value)).cast<std::string>().substr(0, 80))
                                          .c_str());
    throw py::error_already_set();
  }
  out.resize(n);
  std::memcpy(out.data(), a.data(), sizeof(double) * static_cast<size_t>(n));
}

// A scipy.sparse (or dense) matrix from Python into `pattern`'s structure, as `out`.
void into_pattern(const py::object& parts, const py::handle& matrix, const SparseMatrix& pattern, const char* what,
                  SparseMatrix& out) {
  const py::tuple t = parts(matrix, pattern.rows(), what);
  const Index indptr = Index::ensure(t[0]), indices = Index::ensure(t[1]);
  const Array data = Array::ensure(t[2]);
  out = pattern;
  double* values = out.valuePtr();
  const int n = static_cast<int>(pattern.cols());
  const int* p_ptr = pattern.outerIndexPtr();
  const int* p_idx = pattern.innerIndexPtr();
  const int nnz = indptr.at(n);
  if (nnz == pattern.nonZeros() && std::equal(p_ptr, p_ptr + n + 1, indptr.data()) &&
      std::equal(p_idx, p_idx + nnz, indices.data())) {
    std::memcpy(values, data.data(), sizeof(double) * static_cast<size_t>(nnz));
    return;
  }
  std::fill(values, values + pattern.nonZeros(), 0.0);
  for (int j = 0; j < n; ++j) {
    int k = p_ptr[j];
    for (int m = indptr.at(j); m < indptr.at(j + 1); ++m) {
      const int i = indices.at(m);
      while (k < p_ptr[j + 1] && p_idx[k] < i) ++k;
      if (k == p_ptr[j + 1] || p_idx[k] != i) {
        if (data.at(m) == 0.0) continue;  // an explicit zero outside the pattern adds nothing
        PyErr_SetString(PyExc_ValueError,
                        fmt::format("{}(): entry ({}, {}) is outside the Jacobian's pattern (jacobian_pattern(), or "
                                    "the Jacobian at the initial guess where the class has no jacobian_pattern): "
                                    "define jacobian_pattern() with every entry that can be nonzero",
                                    what, i, j)
                            .c_str());
        throw py::error_already_set();
      }
      values[k] = data.at(m);
    }
  }
}

std::vector<std::string> names_of(const py::object& obj, const char* attribute) {
  if (!py::hasattr(obj, attribute)) return {};
  py::object names = obj.attr(attribute);
  if (PyCallable_Check(names.ptr())) names = names();
  return names.cast<std::vector<std::string>>();
}

// Values of named outputs (observables, monitors): a mapping by name or a sequence in their order.
std::vector<double> named_values(const py::object& value, const std::vector<std::string>& names, const char* what) {
  std::vector<double> out;
  if (py::isinstance<py::dict>(value)) {
    const py::dict d = value;
    for (const std::string& n : names) {
      if (!d.contains(n)) {
        PyErr_SetString(PyExc_KeyError, fmt::format("{}() returned no value for '{}'", what, n).c_str());
        throw py::error_already_set();
      }
      out.push_back(d[n.c_str()].cast<double>());
    }
    return out;
  }
  Vector v;
  from_numpy(value, static_cast<int>(names.size()), what, v);
  return {v.data(), v.data() + v.size()};
}

}  // namespace

PythonProblem::PythonProblem(py::object problem) {
  py::gil_scoped_acquire gil;
  obj_ = std::move(problem);
  const py::module_ module = py::module_::import("keller.problem");
  failure_type_ = module.attr("NumericalFailure");
  sparse_parts_ = module.attr("csc_parts");
  name_ = py::hasattr(obj_, "name") ? py::str(obj_.attr("name")).cast<std::string>()
                                    : py::str(obj_.get_type().attr("__name__")).cast<std::string>();
  const py::object declared = obj_.attr("parameters");
  for (const auto& [key, value] : py::dict(declared)) {
    const std::string doc = py::hasattr(obj_, "parameter_docs") && py::dict(obj_.attr("parameter_docs")).contains(key)
                                ? py::str(py::dict(obj_.attr("parameter_docs"))[key]).cast<std::string>()
                                : "a parameter of the Python problem";
    params_.add(py::str(key).cast<std::string>(), value.cast<double>(), doc);
  }
  if (params_.size() == 0) throw std::invalid_argument(name_ + ": a Python problem needs at least one parameter");
  has_jacobian_ = py::hasattr(obj_, "jacobian");
  has_dfdp_ = py::hasattr(obj_, "parameter_derivative");
  has_mass_ = py::hasattr(obj_, "mass_matrix");
  observable_names_ = names_of(obj_, "observable_names");
  monitor_names_ = names_of(obj_, "monitor_names");
  if (py::hasattr(obj_, "residual_scale")) residual_scale_ = obj_.attr("residual_scale").cast<double>();
  summary_ = py::hasattr(obj_, "summary") ? py::str(obj_.attr("summary")()).cast<std::string>() : name_;
  Vector u0;
  const py::object guess = obj_.attr("initial_guess")(parameter_dict());
  from_numpy(guess, static_cast<int>(py::len(guess)), "initial_guess", u0);
  size_ = static_cast<int>(u0.size());
  // the pattern: the class's own, else the Jacobian's at the initial guess, else dense
  py::object pattern;
  if (py::hasattr(obj_, "jacobian_pattern"))
    pattern = obj_.attr("jacobian_pattern")();
  else if (has_jacobian_)
    pattern = obj_.attr("jacobian")(to_numpy(u0), parameter_dict());
  else
    pattern = py::module_::import("numpy").attr("ones")(py::make_tuple(size_, size_));
  const py::tuple t = sparse_parts_(pattern, size_, "jacobian_pattern");
  const Index indptr = Index::ensure(t[0]), indices = Index::ensure(t[1]);
  const int nnz = indptr.at(size_);
  std::vector<Eigen::Triplet<double, int>> triplets;
  triplets.reserve(static_cast<size_t>(nnz));
  for (int j = 0; j < size_; ++j)
    for (int m = indptr.at(j); m < indptr.at(j + 1); ++m) triplets.emplace_back(indices.at(m), j, 0.0);
  pattern_.resize(size_, size_);
  pattern_.setFromTriplets(triplets.begin(), triplets.end());
  pattern_.makeCompressed();
}

PythonProblem::~PythonProblem() {
  py::gil_scoped_acquire gil;
  obj_ = py::object();
  failure_type_ = py::object();
  sparse_parts_ = py::object();
}

py::dict PythonProblem::parameter_dict() const {
  py::dict d;
  for (int i = 0; i < params_.size(); ++i) d[py::str(params_.info(i).name)] = params_.value(i);
  return d;
}

py::object PythonProblem::call(const char* method, const Vector& u) {
  return obj_.attr(method)(to_numpy(u), parameter_dict());
}

template <class Body>
Status PythonProblem::guarded(const char* method, Body&& body) {
  py::gil_scoped_acquire gil;
  try {
    body();
    return {};
  } catch (py::error_already_set& e) {
    if (e.matches(failure_type_))
      return {StatusCode::InvalidState, fmt::format("{}(): {}", method, py::str(e.value()).cast<std::string>())};
    const std::string what = e.what();
    keep_exception(e);
    // the user's code, not a defect of keller: the command stops as an interrupted one does, keeping
    // what it completed (the same call continues it)
    throw CommandFailure(exit_code::interrupted,
                         fmt::format("the Python problem's {}() raised {}: stopped (the exception is raised again in "
                                     "Python)",
                                     method, what));
  }
}

namespace {

// NaN or Inf in what a Python method returned (an exp that overflowed) is a failed evaluation, as
// it is for keller's C++ problems.
Status finite(const char* method, const double* values, long n, Status st) {
  if (!st.is_ok()) return st;
  for (long i = 0; i < n; ++i)
    if (!std::isfinite(values[i]))
      return {StatusCode::NotFinite, fmt::format("{}() of the Python problem is not finite (entry {})", method, i)};
  return st;
}

}  // namespace

Status PythonProblem::residual(const Vector& u, Vector& F) {
  const Status st = guarded("residual", [&] { from_numpy(call("residual", u), size_, "residual", F); });
  return finite("residual", F.data(), F.size(), st);
}

Status PythonProblem::jacobian(const Vector& u, Vector& F, SparseMatrix& J) {
  if (!has_jacobian_) return Problem::jacobian(u, F, J);
  if (Status st = residual(u, F); !st.is_ok()) return st;
  const Status st =
      guarded("jacobian", [&] { into_pattern(sparse_parts_, call("jacobian", u), pattern_, "jacobian", J); });
  return finite("jacobian", J.valuePtr(), J.nonZeros(), st);
}

Status PythonProblem::parameter_derivative(int p, const Vector& u, Vector& dF) {
  if (!has_dfdp_) return Problem::parameter_derivative(p, u, dF);
  const Status st = guarded("parameter_derivative", [&] {
    from_numpy(obj_.attr("parameter_derivative")(to_numpy(u), parameter_dict(), params_.info(p).name), size_,
               "parameter_derivative", dF);
  });
  return finite("parameter_derivative", dF.data(), dF.size(), st);
}

Status PythonProblem::mass_matrix(const Vector& u, SparseMatrix& B) {
  if (!has_mass_) return Problem::mass_matrix(u, B);
  return guarded("mass_matrix",
                 [&] { into_pattern(sparse_parts_, call("mass_matrix", u), pattern_, "mass_matrix", B); });
}

Vector PythonProblem::initial_guess() {
  Vector u0;
  const Status st = guarded(
      "initial_guess", [&] { from_numpy(obj_.attr("initial_guess")(parameter_dict()), size_, "initial_guess", u0); });
  if (!st.is_ok()) throw std::runtime_error(st.describe());
  return u0;
}

Status PythonProblem::observables(const Vector& u, std::vector<double>& values) {
  if (observable_names_.empty()) return Problem::observables(u, values);
  return guarded("observables",
                 [&] { values = named_values(call("observables", u), observable_names_, "observables"); });
}

Status PythonProblem::monitors(const Vector& u, std::vector<double>& values) {
  if (monitor_names_.empty()) return Problem::monitors(u, values);
  return guarded("monitors", [&] { values = named_values(call("monitors", u), monitor_names_, "monitors"); });
}

CurrentProblem::CurrentProblem(py::object problem) {
  if (!problem.is_none()) g_current = std::move(problem);
}

CurrentProblem::~CurrentProblem() { g_current.reset(); }

void register_python_type() {
  ProblemType type;
  type.name = "python";
  type.doc = "a problem written in Python (a keller.Problem), run by keller.solve, trace or evolve with problem=";
  type.declare = [](SceneSchema& s) {
    if (!g_current) return;
    py::gil_scoped_acquire gil;
    // what the problem is, its physics for the files (a stored point starts only a run of the
    // same problem): its name and summary, which say its discretisation where the class says it
    const py::object& obj = *g_current;
    const std::string name = py::hasattr(obj, "name") ? py::str(obj.attr("name")).cast<std::string>()
                                                      : py::str(obj.get_type().attr("__name__")).cast<std::string>();
    s.section("python", "the problem written in Python (set by keller.trace(..., problem=...), not by a scene)");
    s.string("python.problem",
             py::hasattr(obj, "summary") ? name + ": " + py::str(obj.attr("summary")()).cast<std::string>() : name,
             "the Python problem's name and summary()");
    s.section("parameters", "initial values of the Python problem's named parameters");
    for (const auto& [key, value] : py::dict(g_current->attr("parameters")))
      s.real("parameters." + py::str(key).cast<std::string>(), value.cast<double>(),
             "a parameter of the Python problem");
  };
  type.build = [](const Scene& s) -> std::unique_ptr<Problem> {
    if (!g_current)
      throw s.error("problem.type",
                    "'python' is a problem written in Python: run it from Python, keller.trace(scene, problem=...)");
    auto problem = std::make_unique<PythonProblem>(*g_current);
    ParameterSet& p = problem->parameters();
    for (int i = 0; i < p.size(); ++i) p.set(i, s.real("parameters." + p.info(i).name));
    return problem;
  };
  register_problem_type(std::move(type));
}

void keep_exception(py::error_already_set& e) {
  if (!g_kept) g_kept = e;
}

void raise_kept_exception() {
  if (!g_kept) return;
  py::error_already_set e = std::move(*g_kept);
  g_kept.reset();
  throw e;
}

}  // namespace keller::python
