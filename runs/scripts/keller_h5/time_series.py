"""Time series of `keller evolve`: the table of its steps and the mode a run was perturbed along."""

from keller_h5.h5 import open_h5, read_table


def read_time_series(path):
    """Returns ({column: array}, status, mode) of a time-series file; mode is None or
    (sigma_re, sigma_im) of the eigenvector the run was perturbed along."""
    with open_h5(path) as f:
        columns, status = read_table(f["evolve"])
        mode = None
        if "evolve_start" in f and "mode" in f["evolve_start"]:
            m = f["evolve_start"]["mode"]
            mode = (float(m.attrs["sigma_re"]), float(m.attrs["sigma_im"]))
        return columns, status, mode
