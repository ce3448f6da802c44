"""Steady states of `keller solve` (/solution, docs/output.md): fields, parameters, observables,
the Newton history and, with [stability], the spectrum."""

import numpy as np

from keller.files.fields import State
from keller.files.h5 import RunFile, attributes, names, read_rows
from keller.files.table import Table


class Solution(RunFile, State):
    """A file of `keller solve`: `u` (the state vector), `fields` and `mesh` (deformed where there
    is a position field), `parameters` and `observables` (dicts of the state), `newton` (a Table
    of its iterations), `status` (None: a solve writes its file only once solved), and with
    [stability] `stability` (a Table: sigma_re, sigma_im, residual, by real part), `eigenvalues`
    (complex) and `unstable` (the count, neutral ones not counted); None without it."""

    def __init__(self, path):
        State.__init__(self, str(path), "solution/fields", "solution/u")
        RunFile.__init__(self, path)

    def _read(self, f):
        s = f["solution"]
        self.parameters = attributes(s["parameters"]) if "parameters" in s else self.parameters
        self.observables = attributes(s["observables"]) if "observables" in s else {}
        n = s["newton"]
        self.newton = Table.from_rows(names(n.attrs["columns"]), read_rows(n))
        self.final_residual_norm = float(n.attrs["final_residual_norm"]) if "final_residual_norm" in n.attrs else None
        self.status = None
        self.stability = self.eigenvalues = self.unstable = None
        if "stability" in s:
            st = s["stability"]
            self.stability = Table.from_rows(names(st.attrs["columns"]), read_rows(st))
            self.eigenvalues = self.stability["sigma_re"] + 1j * self.stability["sigma_im"]
            self.unstable = int(st.attrs["unstable"])
        self.eigenvalues = None if self.eigenvalues is None else np.asarray(self.eigenvalues)
