"""Study tables of `keller study` (STUDY.h5: /study/<column>, the order in the attribute columns)."""

import numpy as np

from keller_h5.h5 import open_h5, text


def read_study(path):
    """Returns ({column: array of numbers or of strings}, column order) of a study table."""
    with open_h5(path) as f:
        s = f["study"]
        order = text(s.attrs["columns"]).split(",")
        cols = {}
        for c in order:
            v = s[c][()]
            if v.dtype.kind in "SO":
                v = np.array([text(x) for x in v])
            cols[c] = v
        return cols, order


def same_value(cell, value):
    """Whether a varied value of a study table (a number, or TOML text such as "owens", 0.000495,
    M2) is value (a string, or a number compared to 1e-9 relative)."""
    cell_text = str(cell).strip().strip('"')
    try:
        a, b = float(cell_text), float(str(value).strip('"'))
        return abs(a - b) <= 1e-9 * max(1.0, abs(b))
    except ValueError:
        return cell_text == str(value).strip('"')
