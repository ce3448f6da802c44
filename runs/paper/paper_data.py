"""What the figures of runs/paper read: the tables of the studies that make_all.py runs, the
branch file of each task, and the solutions stored on a branch (at its start, its requested
values, its events and its end). Reads only keller's HDF5 files, through the keller package
(keller.open)."""

import os

import numpy as np

import keller
import keller.results
from keller.results import same_value


class MissingData(Exception):
    """A task or stored solution a figure needs is not there (its study has not run, or failed)."""


class Study:
    """The table of a study run into FOLDER (keller study STUDY.toml -o FOLDER)."""

    def __init__(self, folder):
        self.folder = folder
        self.name = os.path.basename(os.path.normpath(folder))
        table = os.path.join(folder, self.name + ".h5")
        if not os.path.exists(table):
            raise MissingData(f"no study table {table} (run the study first)")
        study = keller.Study(table)
        self.cols, self.order = dict(study.table.items()), study.columns
        self.table = table

    def rows(self, where):
        """Indices of the tasks whose varied keys have the given values ({"fluid.model": "owens",
        "parameters.Gamma": 4.95e-4, "mesh.name": "M2"})."""
        sel = []
        for i in range(len(self.cols["name"])):
            ok = True
            for key, v in where.items():
                if key not in self.cols:
                    raise KeyError(f"study {self.name} varies no key '{key}' (it varies: {', '.join(self.order)})")
                ok = ok and same_value(self.cols[key][i], v)
            if ok:
                sel.append(i)
        return sel

    def branch(self, where):
        """The Branch of the one task with these values; MissingData if it is absent or failed."""
        sel = self.rows(where)
        if len(sel) != 1:
            raise MissingData(f"study {self.name}: {len(sel)} tasks match {where}")
        i = sel[0]
        path = os.path.join(self.folder, "tasks", self.cols["name"][i] + ".h5")
        if self.cols["status"][i] != "done" or not os.path.exists(path):
            raise MissingData(f"study {self.name}: task {self.cols['name'][i]} is {self.cols['status'][i]}")
        return Branch(path)

    def value(self, column, where):
        """A collected value (event:min_m1, dP@0.1, end:x_min_m1, ...) of the one matching task."""
        sel = self.rows(where)
        if len(sel) != 1:
            raise MissingData(f"study {self.name}: {len(sel)} tasks match {where}")
        return float(self.cols[column][sel[0]])


class Branch:
    """A branch file of keller trace: its table, and the solutions stored on it (a stored
    solution is a keller.StoredSolution; the figures pass it back to the methods here)."""

    def __init__(self, path):
        self.path = path
        self.branch = keller.open(path)
        self.parameter, self.status = self.branch.parameter, self.branch.status
        # located rows in their order along the branch
        self.cols = dict(self.branch.table.sorted_by("s").items())
        # [(parameter value, row, stored solution)] of the solutions whose fields are stored
        self.saved = [(s.value, s.row, s) for s in self.branch.solutions if s.fields]

    def __getitem__(self, column):
        return self.cols[column]

    def end(self, column):
        return self.cols[column][-1]

    def solution(self, value):
        """The stored solution at parameter value (a start, a stop, the end): its group name."""
        for v, _, g in self.saved:
            if abs(v - value) <= 1e-6 * max(abs(value), 1e-12):
                return g
        have = ", ".join(f"{v:.4g}" for v, _, _ in self.saved)
        raise MissingData(f"{self.path}: no stored solution at {self.parameter} = {value:g} (stored: {have})")

    def last_solution(self):
        return self.saved[-1][2]

    def stored_values(self, upto=None):
        """Parameter values of the stored solutions (up to a value), in branch order."""
        return [v for v, _, _ in self.saved if upto is None or v <= upto * (1 + 1e-9)]

    def array(self, solution, name):
        a = solution.fields.get(name)
        if a is None:
            raise MissingData(f"{self.path}: the stored solution at row {solution.row} has no {name}")
        return np.asarray(a)

    def conformation(self, solution):
        """M at the nodes (xx, xy, yy, ...): the log form stores M beside Psi as conformation_M."""
        a = solution.fields.get("conformation_M")
        return np.asarray(a) if a is not None else self.array(solution, "conformation")

    def triangulation(self, solution):
        """(matplotlib triangulation of the deformed fluid mesh, node positions)."""
        return solution.triangulation("fluid"), solution.mesh.nodes

    def pressure(self, solution, pos):
        """The P1disc pressure at the nodes `pos` (the deformed positions of the solution)."""
        m = solution.mesh
        return keller.results.Mesh(pos, m.elements, m.element_group, m.group_names, m.boundaries).nodal_pressure(
            solution.fields["pressure"])

    def attribute(self, path, name):
        return self.branch.attribute(path, name)

    def mesh(self):
        """(reference node positions, 9-node elements, element group names per element). The
        reference positions are a stored state's positions less its displacement (/mesh/nodes
        holds the deformed mesh of a collapsible-channel branch)."""
        solution = self.saved[0][2]
        m = solution.mesh
        return solution.undeformed_nodes(), m.elements, [m.group_names[g] for g in m.element_group]
