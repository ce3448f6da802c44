"""What every keller HDF5 file shares: opening it (also one whose writer was killed), its text,
its tables (a group holding `table`, its `columns` attribute and `status`) and the resolved scene
it stores."""

import h5py
import numpy as np


def open_h5(path):
    """Opens a keller HDF5 file read-only, falling back to SWMR mode for a killed run."""
    try:
        return h5py.File(path, "r")
    except OSError:
        return h5py.File(path, "r", swmr=True)


def text(value):
    """A string of an HDF5 attribute or dataset (stored as bytes or str)."""
    return value.decode() if isinstance(value, bytes) else str(value)


def read_attribute(path, obj, name):
    """The attribute `name` of the object `obj` (a group or dataset path) of a keller file; text
    as str, numbers as they are stored."""
    with open_h5(path) as f:
        v = f[obj].attrs[name]
    return v.decode() if isinstance(v, bytes) else v


def read_table(group):
    """({column: array}, status) of an open group holding a table (its columns attribute) and a
    status."""
    columns = text(group.attrs["columns"]).split(",")
    table = np.array(group["table"][()], dtype=float).reshape(-1, len(columns))
    status = text(group["status"][()])
    return {c: table[:, i] for i, c in enumerate(columns)}, status.rstrip("\x00")


def scene_values(path):
    """The resolved scene stored in a keller file, as {section.key: value text}."""
    with open_h5(path) as f:
        scene = text(f["scene"][()])
    values, section = {}, ""
    for line in scene.splitlines():
        line = line.split("#", 1)[0].strip() if not line.strip().startswith("#") else ""
        if not line:
            continue
        if line.startswith("[") and line.endswith("]"):
            section = line[1:-1]
        elif "=" in line:
            k, v = line.split("=", 1)
            values[f"{section}.{k.strip()}"] = v.strip().strip('"')
    return values
