"""Branch files of `keller trace` (docs/output.md): the table of its points as named columns, the
kind of each row by name, the located points with the labels `keller info` prints (AUTO's:
`fold1`, `bp2`, `hopf1`, `event1`, `stop4`, `start`, `end`), the stored solutions with their
tangents, fields and critical eigenvectors, and the stability columns. A two-parameter curve
(`keller trace --curve`) is a Curve: a branch with its second parameter."""

import re

import numpy as np

from keller.files.fields import State, read_fields
from keller.files.h5 import RunFile, names, open_h5, read_rows, text
from keller.files.table import Table, TableView

# the kind column's numbers by the names the CSV export, the terminal and the labels use
KINDS = ("point", "start", "stop", "event", "fold", "bp", "end", "hopf", "pd", "ns")
# the kinds of the located points: those that have labels (runs/PointLabels.cpp)
LOCATED = KINDS[1:]


def point_labels(kinds, rows):
    """[(label, row)] of the located points of a table whose kind names and row numbers are given,
    in table order: the kind and its 1-based count, `start` and `end` alone where there is one
    (runs/PointLabels.cpp)."""
    total = {k: 0 for k in KINDS}
    for k in kinds:
        total[k] += 1
    count, out = {k: 0 for k in KINDS}, []
    for k, r in zip(kinds, rows):
        if k == "point":
            continue
        count[k] += 1
        alone = k in ("start", "end") and total[k] == 1
        out.append((k if alone else f"{k}{count[k]}", int(r)))
    return out


def parse_label(label):
    """(kind, k) of a label (`fold` is `fold1`); None for text that is not one."""
    for kind in LOCATED:
        if label.startswith(kind):
            number = label[len(kind):]
            if number == "":
                return kind, 1
            if re.fullmatch(r"[1-9][0-9]{0,8}", number):
                return kind, int(number)
    return None


class StoredSolution(State):
    """A solution stored on a branch (/branch/solutions): its table `row`, `kind` (a name),
    `label` (or None for a regular point), `value` of the branch's parameter, the state `u`, its
    unit `tangent` and the tangent's parameter part, the `step` and arclength `s`, its `fields`
    and `mesh` (deformed where there is a position field), and `eigenvector` (the critical one,
    complex, with `sigma`, and `mode_fields`, where the run had [stability])."""

    def __init__(self, path, slot, saved_row, fields_group, label):
        super().__init__(path, fields_group, "branch/solutions", slot)
        self.slot = slot
        self.row = int(saved_row["row"])
        self.kind = KINDS[int(saved_row["kind"])]
        self.value = float(saved_row["parameter"])
        self.tangent_parameter = float(saved_row["tangent_parameter"])
        self.step, self.s = float(saved_row["step"]), float(saved_row["s"])
        self.label = label
        self._tangent = None
        self.sigma, self._eigen_index = None, None

    @property
    def tangent(self):
        """The unit tangent's state part (its parameter part: tangent_parameter)."""
        if self._tangent is None:
            with open_h5(self.path) as f:
                self._tangent = np.array(f["branch/tangents"][self.slot])
        return self._tangent

    @property
    def eigenvector(self):
        """The critical eigenvector (complex) stored with this point, or None."""
        if self._eigen_index is None:
            return None
        with open_h5(self.path) as f:
            v = f["branch/eigenvectors"]
            return np.array(v[2 * self._eigen_index]) + 1j * np.array(v[2 * self._eigen_index + 1])

    @property
    def mode_fields(self):
        """The critical eigenmode as fields (/branch/modes/<k>: the linear change of each field
        along the eigenvector's real and imaginary parts, on the deformed mesh), as {'re': {name:
        Field}, 'im': {...}}; None where the file has none for this point."""
        if self._eigen_index is None:
            return None
        with open_h5(self.path) as f:
            group = f"branch/modes/{self._eigen_index}"
            if group not in f:
                return None
            return {part: read_fields(f[group][part]) for part in ("re", "im") if part in f[group]}

    def __repr__(self):
        return f"StoredSolution(row {self.row}, {self.label or self.kind}, value {self.value:.10g})"


class Point:
    """A row of a branch table: its `index` in the table, `row` number, `kind`, `label` (None for
    a regular point), `value` of the parameter, `values` ({column: value}), the stored
    `solution` at this row (None where none is stored), its `normal_form` (a located fold,
    branch point or Hopf point: Branch.normal_form_at; else None) and the `monitor` whose zero it
    is (an event: "bautin", "fold-hopf", "cusp", a problem's monitor; else None)."""

    def __init__(self, branch, index, label):
        self.index, self.label = index, label
        self.row = int(branch.table["row"][index])
        self.kind = branch.kinds[index]
        self.value = float(branch.table[branch.parameter][index])
        self.values = branch.table.row(index)
        self.solution = branch.solution_at(self.row)
        self.normal_form = branch.normal_form_at(self.row)
        self.monitor = branch._event_monitors.get(self.row)

    def __getitem__(self, column):
        return self.values[column]

    def __repr__(self):
        return f"Point(row {self.row}, {self.label or self.kind}, value {self.value:.10g})"


class Branch(TableView, RunFile):
    """A branch file of `keller trace`: `parameter` (its name), `table` (a Table of named columns,
    rows as stored: `keller export --csv`), `kinds` (a name per row), `status` (why it ended, or
    `running`), `exit_code` (None while running), `observables`, `monitors`, `labels`
    ([(label, row)]), `points(kind)`, `point(label_or_row)`, `solutions` (StoredSolution, in
    row order), `unstable` and `eigenvalues` where the run had [stability], `normal_forms` (a
    Table: a row per located fold, branch point and Hopf point, docs/normal_forms.md).
    `branch["Wi"]` is a column of the table."""

    def _read(self, f):
        b = f["branch"]
        self.parameter = text(b.attrs["parameter"])
        self.table = Table.from_rows(names(b.attrs["columns"]), read_rows(b["table"]))
        self.status = text(b["status"][()])
        code = float(np.asarray(b["exit_code"][()]).ravel()[0]) if "exit_code" in b else -1
        self.exit_code = None if code < 0 else int(code)
        self.observables = names(b.attrs.get("observables", ""))
        self.monitors = names(b.attrs.get("monitors", ""))
        self.kinds = np.array([KINDS[int(k)] for k in self.table["kind"]], dtype=object)
        self.labels = point_labels(self.kinds, self.table["row"])
        # the monitor whose zero each located event (or threshold end) is, by row
        self._event_monitors = {}
        if "events" in b:
            for row, _kind, _value, monitor in read_rows(b["events"]):
                if 0 <= monitor < len(self.monitors):
                    self._event_monitors[int(row)] = self.monitors[int(monitor)]
        self._solutions = self._read_solutions(f)
        self.normal_forms, self._normal_form_types = Table.from_rows(["row", "kind"], []), []
        if "normal_forms" in b:
            nf = b["normal_forms"]
            self.normal_forms = Table.from_rows(names(nf.attrs["columns"]), read_rows(nf))
            self._normal_form_types = names(nf.attrs["types"])

    def normal_form_at(self, row):
        """The normal form of a located row as {column: value} with `type` its name ("fold",
        "pitchfork (supercritical)", "Hopf (subcritical)", "cusp", ...) and `exact` a bool; None where
        the row has none. A Hopf point's also has `l1:NAME` for each observable: l1 with the
        eigenvector scaled so that the observable's derivative along it has modulus 1,
        l1 (amplitude_coefficient / amplitude:NAME)^2, which unlike l1 (max-normalised) compares
        between meshes (docs/normal_forms.md, Conventions)."""
        hits = np.flatnonzero(self.normal_forms["row"] == row)
        if len(hits) == 0:
            return None
        out = self.normal_forms.row(int(hits[-1]))
        out["type"] = self._normal_form_types[int(out["type"])]
        out["exact"] = bool(out["exact"])
        if out["type"].startswith("Hopf"):
            for name in [k[len("amplitude:"):] for k in out if k.startswith("amplitude:")]:
                a = out["amplitude:" + name]
                out["l1:" + name] = out["l1"] * (out["amplitude_coefficient"] / a) ** 2 if a > 0 else float("nan")
        return out

    def _read_solutions(self, f):
        if "branch/saved" not in f:
            return []
        saved = Table.from_rows(names(f["branch/saved"].attrs["columns"]), read_rows(f["branch/saved"]))
        groups = {}  # the fields group of each stored row
        if "branch/fields" in f:
            for g in f["branch/fields"]:
                groups[int(f["branch/fields"][g].attrs["row"])] = f"branch/fields/{g}"
        label_of = dict((r, lab) for lab, r in self.labels)
        out = [StoredSolution(self.path, i, saved.row(i), groups.get(int(saved["row"][i])),
                              label_of.get(int(saved["row"][i]))) for i in range(len(saved))]
        if "branch/eigenvector_rows" in f:
            er = read_rows(f["branch/eigenvector_rows"]).reshape(-1, 4)
            by_row = {s.row: s for s in out}
            for k, (row, _, re_, im) in enumerate(er):
                s = by_row.get(int(row))
                if s is not None:
                    s.sigma, s._eigen_index = complex(re_, im), k
        return sorted(out, key=lambda s: s.row)

    @property
    def solutions(self):
        """The stored solutions (the start, every save_every-th point, the located points, the
        last), in row order."""
        return list(self._solutions)

    def solution_at(self, row):
        """The stored solution of a table row number, or None."""
        for s in self._solutions:
            if s.row == row:
                return s
        return None

    def index_of_row(self, row):
        """The table index of a row number."""
        hits = np.flatnonzero(self.table["row"] == row)
        if len(hits) == 0:
            raise KeyError(f"{self.path}: no row {row}")
        return int(hits[0])

    def points(self, kind=None):
        """The located points (every row but the regular ones), or those of one kind (`fold`,
        `bp`, `hopf`, `event`, `stop`, `start`, `end`, also `point`), in table order."""
        if kind is not None and kind not in KINDS:
            raise ValueError(f"no kind '{kind}'; the kinds: {', '.join(KINDS)}")
        label_of = dict((r, lab) for lab, r in self.labels)
        return [Point(self, i, label_of.get(int(self.table["row"][i]))) for i, k in enumerate(self.kinds)
                if (k == kind if kind is not None else k != "point")]

    def point(self, which):
        """A row by its label (`fold1`, `bp2`, `fold` for `fold1`, `start`, `end`), its number, or
        `last` (the last stored solution), as `--restart FILE:ROW` takes it."""
        if isinstance(which, (int, np.integer)):
            row = int(which)
        elif which == "last":
            if not self._solutions:
                raise KeyError(f"{self.path}: no stored solution")
            row = self._solutions[-1].row
        elif isinstance(which, str) and which.isdigit():
            row = int(which)
        else:
            wanted, row = parse_label(which), None
            if wanted:
                located = [r for lab, r in self.labels if parse_label(lab)[0] == wanted[0]]
                if wanted[1] <= len(located):
                    row = located[wanted[1] - 1]
            if row is None:
                have = ", ".join(f"{lab} (row {r})" for lab, r in self.labels) or "none"
                raise KeyError(f"{self.path}: no located point labelled '{which}'; its labels: {have}")
        label_of = dict((r, lab) for lab, r in self.labels)
        return Point(self, self.index_of_row(row), label_of.get(row))

    @property
    def unstable(self):
        """The count of unstable eigenvalues per row (NaN where not analysed), or None without
        [stability]."""
        return self.table.get("unstable")

    @property
    def eigenvalues(self):
        """The eigenvalues of J phi = sigma B phi per row (rows x count, complex, by real part), or
        None without [stability]."""
        k = 1
        cols = []
        while f"sigma{k}_re" in self.table:
            cols.append(self.table[f"sigma{k}_re"] + 1j * self.table[f"sigma{k}_im"])
            k += 1
        return np.stack(cols, axis=1) if cols else None

    def values_at(self, column, kind):
        """The column's values at the rows of a kind (`fold`, ...)."""
        return self.table[column][self.kinds == kind]


class Curve(Branch):
    """A two-parameter curve (`keller trace --curve`): a branch whose /problem has the `curve`
    attribute (`curve`: fold, hopf or event), continued in `parameter` with the other parameter
    `second_parameter` a column of its table; `curve_from` the point it started from."""

    def _read(self, f):
        super()._read(f)
        self.curve = text(f["problem"].attrs["curve"])
        self.curve_from = text(f["problem"].attrs.get("curve_from", ""))
        # the other parameter is the observable named after a parameter (runs/InfoCommand)
        others = [o for o in self.observables if o in self.parameters and o != self.parameter]
        self.second_parameter = others[-1] if others else None
