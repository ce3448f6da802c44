// keller's command line run from Python in the calling process (keller._keller.run): the GIL is
// released while the command runs and taken by each call into Python (the callback, a problem's
// methods); SIGINT and SIGTERM are the command's while it runs (runs/Interrupts.hpp: it stops after
// its current point, keeping what it completed) and Python's again after.
#pragma once

#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "python/src/python_problem.hpp"

namespace keller::python {

// Runs `args` (a command and its arguments, as after `keller`), calling `callback` (None: none)
// with a dict per point of a trace or step of an evolve ({"command", "row", "kind", "label",
// "values": {name: value}, "u": array}); a callback that returns False or raises stops the run
// as Ctrl-C does. `problem`: the keller.Problem that scenes of type "python" build (None: none).
// Returns (exit code, stopped by the callback, interrupted by a signal).
pybind11::tuple run_command(const std::vector<std::string>& args, pybind11::object callback, pybind11::object problem);

}  // namespace keller::python
