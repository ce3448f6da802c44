#!/usr/bin/env python3
"""One component of a field of a stored solution, in colour over the mesh, for one or several
branch files side by side (the patterns of branches switched at different branch points, say):
any problem on a mesh of 9-node quadrilaterals, keller's own or one of your own
(docs/own_problem.md). The solution is the last one stored on each branch, or the one stored
nearest a row (--row); its parameter value is in the panel's title.

    python3 runs/scripts/plot_field.py BRANCH.h5 [MORE.h5 ...] --field FIELD:COMPONENT [--row N]
        [--labels L ...] -o FIGURE.png

Reads only the HDF5 files."""

import argparse
import os
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.tri as mtri  # noqa: E402

from keller_h5 import OutputError, save_figure  # noqa: E402
from keller_h5.branch import read_branch, saved_solutions  # noqa: E402
from keller_h5.fields import read_array  # noqa: E402
from keller_h5.h5 import open_h5, read_attribute, text  # noqa: E402


def field_component(path, group, field, component):
    """(node positions, values) of FIELD:COMPONENT of the stored solution `group`."""
    values = read_array(path, group, field)
    if values is None:
        raise OutputError(f"{path}: the stored solution {group} has no field '{field}'")
    names = text(read_attribute(path, f"branch/fields/{group}/{field}", "components")).split(",")
    if component not in names:
        raise OutputError(f"{path}: field '{field}' has the components {', '.join(names)}, not '{component}'")
    with open_h5(path) as f:
        nodes = np.array(f["mesh/nodes"][()])
    return nodes, np.asarray(values).reshape(len(nodes), -1)[:, names.index(component)]


def triangles(path):
    """Each 9-node quadrilateral of /mesh split into 8 triangles through its mid-side nodes."""
    with open_h5(path) as f:
        elements = np.array(f["mesh/elements"][()], dtype=int)
    tris = []
    for el in elements:  # lexicographic 3 x 3 node grid
        for j in range(2):
            for i in range(2):
                a, b, c, d = el[i + 3 * j], el[i + 1 + 3 * j], el[i + 3 * (j + 1)], el[i + 1 + 3 * (j + 1)]
                tris += [(a, b, d), (a, d, c)]
    return np.array(tris)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("branch", nargs="+", help="branch files (HDF5) written by trace")
    ap.add_argument("--field", required=True, help="FIELD:COMPONENT, e.g. c:u")
    ap.add_argument("--row", type=int, help="the stored solution nearest this table row (default: the last)")
    ap.add_argument("--labels", nargs="+", help="a panel title per file (default: the file's name)")
    ap.add_argument("-o", "--output", required=True, help="figure file")
    a = ap.parse_args(argv)
    if ":" not in a.field:
        sys.exit(f"plot_field: --field '{a.field}' is not FIELD:COMPONENT")
    if a.labels and len(a.labels) != len(a.branch):
        sys.exit(f"plot_field: {len(a.labels)} labels for {len(a.branch)} files")
    field, component = a.field.split(":", 1)
    try:
        fig, axes = plt.subplots(1, len(a.branch), figsize=(4.2 * len(a.branch), 3.8), squeeze=False)
        for k, (path, ax) in enumerate(zip(a.branch, axes[0])):
            parameter, _, _ = read_branch(path)
            stored = saved_solutions(path)
            if not stored:
                raise OutputError(f"{path}: no stored solution (/branch/fields)")
            value, row, group = stored[-1] if a.row is None else min(stored, key=lambda t: abs(t[1] - a.row))
            nodes, u = field_component(path, group, field, component)
            tri = mtri.Triangulation(nodes[:, 0], nodes[:, 1], triangles(path))
            if u.min() < 0 < u.max():  # a field of both signs: zero white
                m = np.abs(u).max()
                art = ax.tripcolor(tri, u, shading="gouraud", cmap="RdBu_r", vmin=-m, vmax=m)
            else:
                art = ax.tripcolor(tri, u, shading="gouraud", cmap="viridis")
            ax.set_aspect("equal")
            ax.set_xlabel("x")
            ax.set_ylabel("y")
            name = a.labels[k] if a.labels else os.path.splitext(os.path.basename(path))[0]
            ax.set_title(f"{name}: {parameter} = {value:.6g} (row {row})", fontsize=10)
            fig.colorbar(art, ax=ax, shrink=0.6, label=component)
        fig.tight_layout()
        save_figure(fig, a.output, a.branch, dpi=150)
    except OutputError as e:
        sys.exit(f"plot_field: {e}")
    print(f"wrote {a.output}")


if __name__ == "__main__":
    main()
