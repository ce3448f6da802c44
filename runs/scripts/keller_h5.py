"""Reading keller's HDF5 output from Python (h5py), including branch files whose writer was
killed (those open only in SWMR read mode)."""

import h5py
import numpy as np

KINDS = {0: "point", 1: "start", 2: "requested", 3: "event", 4: "fold", 5: "branch point", 6: "end", 7: "Hopf"}


def open_h5(path):
    """Opens a keller HDF5 file read-only, falling back to SWMR mode for a killed run."""
    try:
        return h5py.File(path, "r")
    except OSError:
        return h5py.File(path, "r", swmr=True)


def _attr(obj, name):
    v = obj.attrs[name]
    return v.decode() if isinstance(v, bytes) else str(v)


def read_branch(path):
    """Returns (parameter name, {column: array}, status) of a branch file."""
    with open_h5(path) as f:
        b = f["branch"]
        columns = _attr(b, "columns").split(",")
        table = np.array(b["table"][()], dtype=float).reshape(-1, len(columns))
        status = b["status"][()]
        status = status.decode() if isinstance(status, bytes) else str(status)
        return _attr(b, "parameter"), {c: table[:, i] for i, c in enumerate(columns)}, status.rstrip("\x00")
