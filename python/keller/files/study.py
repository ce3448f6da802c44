"""Studies of `keller study` (STUDY.h5: /study/<column>, the order in the attribute `columns`;
each task's branch in FOLDER/tasks/<name>.h5): the table with numbers and strings, the rows of
given varied values, and a task's branch."""

import os

import numpy as np

from keller.files.h5 import RunFile, names, open_h5, text
from keller.files.table import Table, TableView


def same_value(cell, value):
    """Whether a varied value of a study table (a number, or TOML text such as "owens", 0.000495,
    M2) is value (a string, or a number compared to 1e-9 relative)."""
    cell_text = str(cell).strip().strip('"')
    try:
        a, b = float(cell_text), float(str(value).strip('"'))
        return abs(a - b) <= 1e-9 * max(1.0, abs(b))
    except ValueError:
        return cell_text == str(value).strip('"')


def study_table_path(path):
    """The STUDY.h5 of a study: the file itself, or in a study's folder the .h5 file holding
    /study (the folder's name or the study file's)."""
    path = str(path)
    if not os.path.isdir(path):
        return path
    named = os.path.join(path, os.path.basename(os.path.normpath(path)) + ".h5")
    candidates = [named] if os.path.exists(named) else sorted(
        os.path.join(path, n) for n in os.listdir(path) if n.endswith(".h5"))
    for c in candidates:
        try:
            with open_h5(c) as f:
                if "study" in f:
                    return c
        except OSError:
            continue
    raise FileNotFoundError(f"'{path}' holds no study table (STUDY.h5 with /study)")


class Study(TableView, RunFile):
    """A study's collected table: `table` (a Table: numbers as floats, text columns such as name,
    status and the varied keys as strings), `columns`, `tasks` (the task names), `folder`;
    `rows(where)`, `value(column, where)` and `branch(task)` (the task's Branch)."""

    def __init__(self, path):
        super().__init__(study_table_path(path))
        self.folder = os.path.dirname(os.path.abspath(self.path))

    def _read(self, f):
        s = f["study"]
        cols = {}
        for c in names(s.attrs["columns"]):
            v = s[c][()]
            cols[c] = np.array([text(x) for x in v]) if v.dtype.kind in "SO" else np.asarray(v)
        self.table = Table(cols)

    @property
    def tasks(self):
        return list(self.table["name"])

    @property
    def status(self):
        """{status: count} of the tasks (done, failed, ...)."""
        out = {}
        for s in self.table["status"]:
            out[s] = out.get(s, 0) + 1
        return out

    def rows(self, where):
        """Indices of the tasks whose varied keys have the given values ({"fluid.model": "owens",
        "parameters.Gamma": 4.95e-4}; numbers compared to 1e-9 relative: same_value)."""
        for key in where:
            if key not in self.table:
                raise KeyError(f"study {self.path} has no column '{key}'; its columns: {', '.join(self.columns)}")
        return [i for i in range(len(self)) if all(same_value(self.table[k][i], v) for k, v in where.items())]

    def value(self, column, where):
        """A collected value (event:min_m1, dP@0.1, ...) of the one task matching `where`."""
        sel = self.rows(where)
        if len(sel) != 1:
            raise KeyError(f"study {self.path}: {len(sel)} tasks match {where}")
        return self.table[column][sel[0]]

    def task_path(self, task):
        """The branch file of a task: by name, by index in the table, or by {key: value}."""
        if isinstance(task, dict):
            sel = self.rows(task)
            if len(sel) != 1:
                raise KeyError(f"study {self.path}: {len(sel)} tasks match {task}")
            task = sel[0]
        if isinstance(task, (int, np.integer)):
            task = self.table["name"][task]
        if task not in self.tasks:
            raise KeyError(f"study {self.path} has no task '{task}'; its tasks: {', '.join(self.tasks)}")
        return os.path.join(self.folder, "tasks", task + ".h5")

    def branch(self, task):
        """The Branch (or Curve) of a task (task_path)."""
        from keller.results import open as open_result

        return open_result(self.task_path(task))
