"""Reading keller's HDF5 output from Python (h5py), including branch files whose writer was
killed (those open only in SWMR read mode)."""

import os

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


def _table(group):
    """({column: array}, status) of a group holding a table (its columns attribute) and a status."""
    columns = _attr(group, "columns").split(",")
    table = np.array(group["table"][()], dtype=float).reshape(-1, len(columns))
    status = group["status"][()]
    status = status.decode() if isinstance(status, bytes) else str(status)
    return {c: table[:, i] for i, c in enumerate(columns)}, status.rstrip("\x00")


def read_branch(path):
    """Returns (parameter name, {column: array}, status) of a branch file."""
    with open_h5(path) as f:
        columns, status = _table(f["branch"])
        return _attr(f["branch"], "parameter"), columns, status


def read_time_series(path):
    """Returns ({column: array}, status, mode) of a time-series file written by `keller evolve`;
    mode is None or (sigma_re, sigma_im) of the eigenvector the run was perturbed along."""
    with open_h5(path) as f:
        columns, status = _table(f["evolve"])
        mode = None
        if "evolve_start" in f and "mode" in f["evolve_start"]:
            m = f["evolve_start"]["mode"]
            mode = (float(m.attrs["sigma_re"]), float(m.attrs["sigma_im"]))
        return columns, status, mode


def read_study(path):
    """Returns ({column: array of numbers or of strings}, column order) of a study table
    (STUDY.h5 of keller study: /study/<column>, the order in the attribute columns)."""
    with open_h5(path) as f:
        s = f["study"]
        order = _attr(s, "columns").split(",")
        cols = {}
        for c in order:
            v = s[c][()]
            if v.dtype.kind in "SO":
                v = np.array([x.decode() if isinstance(x, bytes) else str(x) for x in v])
            cols[c] = v
        return cols, order


def same_value(cell, value):
    """Whether a varied value of a study table (a number, or TOML text such as "owens", 0.000495,
    M2) is value (a string, or a number compared to 1e-9 relative)."""
    text = str(cell).strip().strip('"')
    try:
        a, b = float(text), float(str(value).strip('"'))
        return abs(a - b) <= 1e-9 * max(1.0, abs(b))
    except ValueError:
        return text == str(value).strip('"')


class OutputError(Exception):
    """An output path that keller's rules refuse (it would overwrite an input, or is not a file)."""


def _same_file(a, b):
    try:
        return os.path.samefile(a, b)
    except OSError:
        return os.path.realpath(a) == os.path.realpath(b)


def check_outputs(outputs, inputs=()):
    """The rules of every file keller writes (core/RunFiles): no output is an input or another
    output (compared by file identity, so ./, .., symbolic and hard links are seen through), and
    a target is a regular file or absent, in an existing folder. Raises OutputError."""
    for i, out in enumerate(outputs):
        if os.path.lexists(out) and not (os.path.isfile(out) and not os.path.islink(out)):
            raise OutputError(f"output '{out}' is not a regular file (a link, directory, FIFO or device)")
        folder = os.path.dirname(out) or "."
        if not os.path.isdir(folder):
            raise OutputError(f"output '{out}': folder '{folder}' does not exist")
        for inp in inputs:
            if _same_file(out, inp):
                raise OutputError(f"output '{out}' is the same file as the input '{inp}'; write to another file")
        for other in outputs[:i]:
            if _same_file(out, other):
                raise OutputError(f"outputs '{other}' and '{out}' are the same file")


def save_figure(fig, path, inputs=(), **savefig_args):
    """Saves a matplotlib figure under PATH.part and renames it to PATH once complete, after
    checking PATH against the inputs (check_outputs)."""
    check_outputs([path], inputs)
    fmt = os.path.splitext(path)[1].lstrip(".") or "png"
    tmp = path + ".part"
    try:
        fig.savefig(tmp, format=fmt, **savefig_args)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


# What each parameter and observable is, with its scaling (model.md: lengths in W, pressures and
# stresses in G, velocities in G W / eta0), for axis labels.
QUANTITIES = {
    "Wi": "Wi (inlet Weissenberg number)",
    "Gamma": r"$\Gamma = \eta_0 U_0 / (G W)$",
    "t": "wall thickness t / W",
    "Pe": "external pressure Pe / G",
    "Re": "Re",
    "beta": r"$\beta = \eta_s / \eta_0$",
    "dP": "pressure drop across the wall, dP / G",
    "dP_inlet_outlet": "pressure drop inlet to outlet, dP_inlet_outlet / G",
    "eta": "viscosity eta / eta0",
    "eta_p": "polymer viscosity eta_p / eta_p0",
    "Wi_local": "local Wi = lambda_0 gdot",
    "rate": "shear rate (1/s)",
    "log10_rate": "log10 of the shear rate (1/s)",
    "dx_max": "x of largest deflection from the centre, dx_max / W",
    "dy_max": "largest deflection dy_max / W",
    "gap_min": "narrowest gap / W",
    "min_m1": "min m1 (smallest eigenvalue of M)",
    "max_m3": "max m3 (largest eigenvalue of M)",
    "max_trM": "max tr M",
    "drag": r"drag K = $F_x / (\eta_0 U)$",
    "u_mid": "u(1/2)",
    "u_max": "max u",
    "u_quarter": "u(1/4)",
    "lambda": r"$\lambda$",
}


def quantity(name):
    """The axis label of a parameter or observable (its name when it is not a known one)."""
    return QUANTITIES.get(name, name)


def scene_values(path):
    """The resolved scene stored in a keller file, as {section.key: value text}."""
    with open_h5(path) as f:
        text = f["scene"][()]
    text = text.decode() if isinstance(text, bytes) else str(text)
    values, section = {}, ""
    for line in text.splitlines():
        line = line.split("#", 1)[0].strip() if not line.strip().startswith("#") else ""
        if not line:
            continue
        if line.startswith("[") and line.endswith("]"):
            section = line[1:-1]
        elif "=" in line:
            k, v = line.split("=", 1)
            values[f"{section}.{k.strip()}"] = v.strip().strip('"')
    return values


def distinguishing_labels(paths, ignore=()):
    """A label per file from the scene keys whose values differ between the files (for example
    'fluid.model = owens, mesh.name = M3'); the file names when the scenes agree."""
    scenes = [scene_values(p) for p in paths]
    keys = sorted({k for s in scenes for k in s})
    differing = [k for k in keys if len({s.get(k) for s in scenes}) > 1 and not k.startswith("continuation.")
                 and k not in ignore and not k.startswith("output.")]
    if not differing or len(paths) == 1:
        return [os.path.basename(p) for p in paths]
    return [", ".join(f"{k.split('.', 1)[1]} = {s.get(k, '-')}" for k in differing) for s in scenes]
