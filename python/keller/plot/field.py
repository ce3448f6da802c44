"""One component of a field of a stored solution, in colour over the mesh, for one or several
branch files side by side (the patterns of branches switched at different branch points, say):
any problem on a mesh of 9-node quadrilaterals, keller's own or one of your own
(docs/own_problem.md). The solution is the last one stored on each branch, or the one stored
nearest a row (--row); its parameter value is in the panel's title (after a label per file: --labels, or
the scene keys that differ, or how the branch started, 'switched at bp1'; never the file's name).

    python3 -m keller.plot field BRANCH.h5 [MORE.h5 ...] --field FIELD:COMPONENT [--row N]
        [--labels L ...] -o FIGURE.png

Reads only the HDF5 files (keller.open)."""

import argparse
import os
import sys

import numpy as np
import matplotlib.pyplot as plt

import keller.results
from keller.labels import distinguishing_labels, readable, symbol
from keller.outputs import OutputError, save_figure
from keller.plot.branch import origin_labels


def field_component(path, solution, field, component):
    """The values of FIELD:COMPONENT at the nodes of a stored solution."""
    values = solution.fields.get(field)
    if values is None:
        raise OutputError(f"{path}: the stored solution at row {solution.row} has no field '{field}'")
    if component not in values.components:
        raise OutputError(f"{path}: field '{field}' has the components {', '.join(values.components)}, "
                          f"not '{component}'")
    return values.component(component)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("branch", nargs="+", help="branch files (HDF5) written by trace")
    ap.add_argument("--field", required=True, help="FIELD:COMPONENT, e.g. c:u")
    ap.add_argument("--row", type=int, help="the stored solution nearest this table row (default: the last)")
    ap.add_argument("--labels", nargs="+", help="a label per file, before its parameter value in the panel's title")
    ap.add_argument("--title", help="a title over the panels (default: none)")
    ap.add_argument("-o", "--output", required=True, help="figure file")
    a = ap.parse_args(argv)
    if ":" not in a.field:
        sys.exit(f"keller.plot field: --field '{a.field}' is not FIELD:COMPONENT")
    if a.labels and len(a.labels) != len(a.branch):
        sys.exit(f"keller.plot field: {len(a.labels)} labels for {len(a.branch)} files")
    field, component = a.field.split(":", 1)
    try:
        panels, branches = [], []
        for k, path in enumerate(a.branch):
            branch = keller.results.open(path)
            parameter = branch.parameter
            stored = [s for s in branch.solutions if s.fields]
            if not stored:
                raise OutputError(f"{path}: no stored solution (/branch/fields)")
            sol = stored[-1] if a.row is None else min(stored, key=lambda s: abs(s.row - a.row))
            value = sol.value
            u = field_component(path, sol, field, component)
            if sol.mesh is None:
                raise OutputError(f"{path}: no mesh (/mesh): a 1D problem's fields are tables")
            tri = sol.mesh.triangulation()  # on the deformed positions where there are some
            panels.append((tri, u, parameter, value))
            branches.append(branch)
        names = a.labels
        if not names and len(branches) > 1:  # by the scene keys that differ, or how each branch started
            names = [readable(x) for x in distinguishing_labels(a.branch)]
            if names == [os.path.basename(p) for p in a.branch]:
                names = origin_labels(a.branch, branches)
        # the figure shaped by the domain: side by side where it is about square, stacked where
        # it is long (a channel), so that no panel is mostly white space
        xs = np.concatenate([t.x for t, *_ in panels])
        ys = np.concatenate([t.y for t, *_ in panels])
        aspect = (ys.max() - ys.min()) / max(xs.max() - xs.min(), 1e-300)
        n = len(panels)
        if aspect < 0.5:
            fig, axes = plt.subplots(n, 1, figsize=(8.0, n * (8.0 * aspect + 1.1) + 0.2), squeeze=False)
            axes = axes[:, 0]
        else:
            fig, axes = plt.subplots(1, n, figsize=(4.2 * n, 3.6 * min(aspect, 1.6) + 0.6), squeeze=False)
            axes = axes[0]
        for k, (ax, (tri, u, parameter, value)) in enumerate(zip(axes, panels)):
            if u.min() < 0 < u.max():  # a field of both signs: zero white
                m = np.abs(u).max()
                art = ax.tripcolor(tri, u, shading="gouraud", cmap="RdBu_r", vmin=-m, vmax=m)
            else:
                art = ax.tripcolor(tri, u, shading="gouraud", cmap="viridis")
            ax.set_aspect("equal")
            ax.set_xlabel("x")
            ax.set_ylabel("y")
            what = f"{symbol(parameter)} = {value:.6g}"
            ax.set_title(f"{names[k]}\n{what}" if names else what, fontsize=9)
            fig.colorbar(art, ax=ax, shrink=0.6 if aspect < 0.5 else 0.8, label=component, pad=0.02)
        if a.title:
            fig.suptitle(a.title, fontsize=10)
        fig.tight_layout()
        save_figure(fig, a.output, a.branch, dpi=150)
    except OutputError as e:
        sys.exit(f"keller.plot field: {e}")
    print(f"wrote {a.output}")


if __name__ == "__main__":
    main()
