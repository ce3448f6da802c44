#include "python/src/python_runs.hpp"

#include <pybind11/numpy.h>

#include <cstdio>

#include "runs/CommandLine.hpp"
#include "runs/Interrupts.hpp"
#include "runs/RunHooks.hpp"

namespace py = pybind11;

namespace keller::python {

namespace {

py::dict point_dict(const RunPoint& p) {
  py::dict values;
  for (size_t i = 0; i < p.values.size(); ++i) values[py::str(p.names[i])] = p.values[i];
  py::dict d;
  d["command"] = p.command;
  d["row"] = p.row;
  d["kind"] = p.kind;
  d["label"] = p.label;
  d["values"] = values;
  d["u"] = p.u ? py::array_t<double>(p.u->size(), p.u->data()) : py::array_t<double>(0);
  return d;
}

}  // namespace

py::tuple run_command(const std::vector<std::string>& args, py::object callback, py::object problem) {
  const CurrentProblem current(problem);
  bool stopped = false;
  RunHook hook;
  if (!callback.is_none()) {
    hook = [&](const RunPoint& p) {
      py::gil_scoped_acquire gil;
      try {
        const py::object r = callback(point_dict(p));
        if (!r.is_none() && !r.cast<bool>()) stopped = true;
      } catch (py::error_already_set& e) {
        keep_exception(e);
        stopped = true;
      }
      return !stopped;
    };
  }
  const RunHookScope scope(hook);
  std::vector<std::string> words{"keller"};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  int code = 0;
  {
    py::gil_scoped_release release;
    code = run_command_line(static_cast<int>(words.size()), argv.data());
    std::fflush(stdout);
    std::fflush(stderr);
  }
  raise_kept_exception();
  return py::make_tuple(code, stopped, InterruptGuard::requested() && !stopped);
}

}  // namespace keller::python
