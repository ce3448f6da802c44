"""Time series of `keller evolve` (docs/output.md): the table of its steps, the mode a run was
perturbed along, the steady state it started from and the states stored along it."""

import numpy as np

from keller.files.fields import State
from keller.files.h5 import RunFile, names, open_h5, read_rows, text
from keller.files.table import Table, TableView


class Mode:
    """The eigenvector a run was perturbed along (/evolve_start/mode): `sigma` (complex: the
    perturbation grows at -Re sigma) and `vector` (complex)."""

    def __init__(self, sigma, vector):
        self.sigma, self.vector = sigma, vector

    def __repr__(self):
        return f"Mode(sigma = {self.sigma})"


class StoredState(State):
    """A state stored along a time series (/evolve/solutions): its `step`, time `t`, vector `u`,
    `fields` and `mesh`."""

    def __init__(self, path, slot, step, t, fields_group):
        super().__init__(path, fields_group, "evolve/solutions", slot)
        self.slot, self.step, self.t = slot, step, t

    def __repr__(self):
        return f"StoredState(step {self.step}, t = {self.t:.10g})"


class TimeSeries(TableView, RunFile):
    """A time-series file of `keller evolve`: `table` (a Table: step, t, h, ..., the observables,
    deviation), `status`, `exit_code` (None while running), `observables`, `save_every`, `mode`
    (a Mode, or None without a perturbation along an eigenvector), `start_state` (the steady
    state it started from) and `states` (StoredState, in step order). `series["t"]` is a
    column."""

    def _read(self, f):
        e = f["evolve"]
        self.table = Table.from_rows(names(e.attrs["columns"]), read_rows(e["table"]))
        self.status = text(e["status"][()])
        code = float(np.asarray(e["exit_code"][()]).ravel()[0]) if "exit_code" in e else -1
        self.exit_code = None if code < 0 else int(code)
        self.observables = names(e.attrs.get("observables", ""))
        self.save_every = int(e.attrs["save_every"]) if "save_every" in e.attrs else None
        self.mode = None
        if "evolve_start/mode" in f:
            m = f["evolve_start/mode"]
            v = np.array(m[()])
            self.mode = Mode(complex(float(m.attrs["sigma_re"]), float(m.attrs["sigma_im"])), v[0] + 1j * v[1])
        self.start_state = np.array(f["evolve_start/state"][()]) if "evolve_start/state" in f else None
        self._states = []
        if "evolve/saved" in f:
            groups = {}
            if "evolve/fields" in f:
                for g in f["evolve/fields"]:
                    groups[int(f["evolve/fields"][g].attrs["step"])] = f"evolve/fields/{g}"
            saved = read_rows(f["evolve/saved"]).reshape(-1, 2)
            self._states = [StoredState(self.path, i, int(step), float(t), groups.get(int(step)))
                            for i, (step, t) in enumerate(saved)]

    @property
    def states(self):
        """The stored states (every save_every steps, the start and the end), in step order."""
        return list(self._states)

    def history(self):
        """(states, [(step, t)]) of the ring of the last four states a restart continues from."""
        with open_h5(self.path) as f:
            return np.array(f["evolve/history"][()]), read_rows(f["evolve/history_index"])
