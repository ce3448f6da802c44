// keller._keller: the C++ side of the keller Python package (python/keller, docs/python.md). It runs
// keller's commands in the calling process (runs/CommandLine.hpp, with the scene a file or the TOML
// the package writes for a dict), with a callback per point (runs/RunHooks.hpp) and a problem
// written in Python (python_problem.hpp). Everything else of the package is Python.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdio>
#include <string>
#include <vector>

#include "core/BlasThreads.hpp"
#include "python/src/python_runs.hpp"
#include "runs/Provenance.hpp"
#include "runs/study/StudyRunner.hpp"

namespace py = pybind11;

PYBIND11_MODULE(_keller, m) {
  m.doc() = "keller's commands in this process (the package keller calls them: keller.trace, ...)";
  keller::python::register_python_type();
  // numpy may share this process's OpenBLAS: its threads stay as the user has them (core/BlasThreads.hpp)
  keller::set_blas_thread_policy(false);
  m.def("run", &keller::python::run_command, py::arg("args"), py::arg("callback") = py::none(),
        py::arg("problem") = py::none(),
        "Runs the keller command line `args` (without the program's name) in this process; returns (exit code, "
        "stopped by the callback, interrupted by a signal). A Python exception of the callback or the problem is "
        "raised again once the command has stopped.");
  m.def("set_task_program", &keller::set_task_program, py::arg("path"),
        "The keller program that runs a study's tasks, each in its own process (this process is Python's)");
  m.def("provenance", [] {
    const keller::Provenance& p = keller::Provenance::current();
    py::dict d;
    d["version"] = p.version;
    d["commit"] = p.commit;
    return d;
  });
}
