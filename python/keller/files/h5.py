"""What every keller HDF5 file shares: opening it (also one whose writer was killed, which opens
only in SWMR read mode), its text attributes, its tables (a group holding `table`, its `columns`
attribute and `status`), the resolved scene (/scene), what made it (/provenance) and the problem
it solved (/problem). docs/output.md describes the files."""

import tomllib

import h5py
import numpy as np


def open_h5(path):
    """Opens a keller HDF5 file read-only, falling back to SWMR mode for a killed run (its
    superblock still marks a writer, which plain read mode refuses)."""
    try:
        return h5py.File(path, "r")
    except OSError:
        return h5py.File(path, "r", swmr=True)


def text(value):
    """A string of an HDF5 attribute or dataset (stored as bytes or str; fixed-length strings
    padded with NUL)."""
    if isinstance(value, np.ndarray) and value.shape == ():
        value = value[()]
    return (value.decode() if isinstance(value, bytes) else str(value)).rstrip("\x00")


def attribute_value(value):
    """An attribute as Python: text as str, a number as float or int, arrays as they are."""
    if isinstance(value, (bytes, str)):
        return text(value)
    if isinstance(value, np.generic):
        return value.item()
    return value


def attributes(obj):
    """{name: value} of the attributes of an open group or dataset, in their stored order."""
    return {k: attribute_value(v) for k, v in obj.attrs.items()}


def names(value):
    """A comma-separated attribute (`columns`, `observables`) as a list of names; [] for ''."""
    s = text(value)
    return s.split(",") if s else []


def read_attribute(path, obj, name):
    """The attribute `name` of the object `obj` (a group or dataset path) of a keller file; text
    as str, numbers as they are stored."""
    with open_h5(path) as f:
        return attribute_value(f[obj].attrs[name])


def read_rows(dataset):
    """A 2D float table of a dataset (an empty one as 0 x columns)."""
    return np.array(dataset[()], dtype=float)


def scene_values_of(scene_text):
    """The resolved scene text as {section.key: value text} (quotes stripped), the form the
    figures' labels compare files by."""
    values, section = {}, ""
    for line in scene_text.splitlines():
        line = line.split("#", 1)[0].strip() if not line.strip().startswith("#") else ""
        if not line:
            continue
        if line.startswith("[") and line.endswith("]"):
            section = line[1:-1]
        elif "=" in line:
            k, v = line.split("=", 1)
            values[f"{section}.{k.strip()}"] = v.strip().strip('"')
    return values


class RunFile:
    """What every file keller writes holds: its path, the resolved scene (`scene`: a nested dict
    parsed by tomllib; `scene_text`: as stored), `provenance` ({keller_version, commit,
    build_type, linear_solver, command_line}; {} for a file of an older keller), `problem` (the
    attributes of /problem: name, summary, unknowns, ...) and `parameters` (/problem/parameters:
    the parameter values at the start)."""

    def __init__(self, path):
        self.path = str(path)
        with open_h5(self.path) as f:
            self.scene_text = text(f["scene"][()]) if "scene" in f else ""
            self.provenance = attributes(f["provenance"]) if "provenance" in f else {}
            self.problem = attributes(f["problem"]) if "problem" in f else {}
            self.parameters = attributes(f["problem/parameters"]) if "problem/parameters" in f else {}
            self._read(f)
        self.scene = tomllib.loads(self.scene_text) if self.scene_text else {}

    def _read(self, f):
        """Reads what the kind of file holds beyond the common part (the subclasses)."""

    def scene_values(self):
        """The scene as {section.key: value text} (see scene_values_of)."""
        return scene_values_of(self.scene_text)

    def attribute(self, obj, name):
        """An attribute of an object of the file (read_attribute)."""
        return read_attribute(self.path, obj, name)

    def __repr__(self):
        return f"{type(self).__name__}({self.path!r})"


def scene_values(path):
    """The resolved scene stored in a keller file, as {section.key: value text}; {} where the file
    stores none."""
    with open_h5(path) as f:
        return scene_values_of(text(f["scene"][()])) if "scene" in f else {}
