"""Results as objects: `keller.open(path)` reads any file keller writes and returns, by what it
holds, a Branch (`keller trace`), a Curve (`keller trace --curve`), a TimeSeries (`keller
evolve`), a Solution (`keller solve`) or a Study (`keller study`: its STUDY.h5 or its folder).
A file still being written, or whose run was killed, opens too (in SWMR read mode).

    import keller
    b = keller.open("gamma.h5")
    b.parameter, b.columns, b["dy_max"], b.kinds, b.labels, b.status
    fold = b.point("fold1"); fold.value; fold.solution.fields["velocity"]
    b.solutions[-1].mesh.nodes          # the deformed mesh of the last stored solution

docs/python.md describes the objects, docs/output.md the files."""

import os

from keller.files.branch import KINDS, Branch, Curve, Point, StoredSolution, point_labels
from keller.files.fields import Field, Mesh, State
from keller.files.h5 import open_h5
from keller.files.solution import Solution
from keller.files.study import Study, same_value
from keller.files.table import Table
from keller.files.time_series import Mode, StoredState, TimeSeries

__all__ = ["KINDS", "Branch", "Curve", "Field", "Mesh", "Mode", "Point", "Solution", "State", "StoredSolution",
           "StoredState", "Study", "Table", "TimeSeries", "kind_of", "open", "point_labels", "same_value"]


def kind_of(path):
    """What a keller file holds: 'branch', 'curve', 'time series', 'solution' or 'study'
    (a folder: 'study'); ValueError for a file keller did not write."""
    path = os.fspath(path)
    if os.path.isdir(path):
        return "study"
    with open_h5(path) as f:
        if "branch" in f:
            return "curve" if "problem" in f and "curve" in f["problem"].attrs else "branch"
        if "evolve" in f:
            return "time series"
        if "solution" in f:
            return "solution"
        if "study" in f:
            return "study"
    raise ValueError(f"'{path}' is not a file keller writes (no /branch, /evolve, /solution or /study)")


def open(path):  # noqa: A001 (keller.open, as h5py.File and tables open files)
    """The object of a keller file, by its content (kind_of): Branch, Curve, TimeSeries,
    Solution or Study."""
    if not os.path.exists(os.fspath(path)):
        raise FileNotFoundError(f"no file '{os.fspath(path)}'")
    return {"branch": Branch, "curve": Curve, "time series": TimeSeries, "solution": Solution,
            "study": Study}[kind_of(path)](os.fspath(path))

