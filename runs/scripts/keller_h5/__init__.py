"""Reading keller's HDF5 output from Python (h5py), including files whose writer was killed
(those open only in SWMR read mode): branch files (`keller trace`), the fields stored on them,
study tables (`keller study`) and time series (`keller evolve`), with what the figure scripts
share (axis labels, the rules of the files they write). docs/output.md describes the files.

The scripts of runs/scripts import it as `keller_h5` (their folder is on Python's path when they
run); runs/paper and runs/bench reach it through the link of that name in their folders."""

from keller_h5.branch import KINDS, read_branch, saved_solutions
from keller_h5.fields import nodal_pressure, read_array, read_mesh, triangulation
from keller_h5.h5 import open_h5, read_attribute, scene_values
from keller_h5.labels import QUANTITIES, distinguishing_labels, quantity
from keller_h5.outputs import OutputError, check_outputs, save_figure
from keller_h5.study import read_study, same_value
from keller_h5.time_series import read_time_series

__all__ = [
    "KINDS", "OutputError", "QUANTITIES", "check_outputs", "distinguishing_labels", "nodal_pressure", "open_h5",
    "quantity", "read_array", "read_attribute", "read_branch", "read_mesh", "read_study", "read_time_series",
    "same_value", "save_figure", "saved_solutions", "scene_values", "triangulation",
]
