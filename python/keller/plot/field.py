"""One component of a field of a stored solution, in colour over the mesh, for one or several
branch files side by side (the patterns of branches switched at different branch points, say):
any problem on a mesh of 9-node quadrilaterals, keller's own or one of your own
(docs/own_problem.md). The solution is the last one stored on each branch, or the one stored
nearest a row (--row); its parameter value is in the panel's title.

    python3 -m keller.plot field BRANCH.h5 [MORE.h5 ...] --field FIELD:COMPONENT [--row N]
        [--labels L ...] -o FIGURE.png

Reads only the HDF5 files (keller.open)."""

import argparse
import os
import sys

import numpy as np
import matplotlib.pyplot as plt

import keller.results
from keller.outputs import OutputError, save_figure


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
    ap.add_argument("--labels", nargs="+", help="a panel title per file (default: the file's name)")
    ap.add_argument("-o", "--output", required=True, help="figure file")
    a = ap.parse_args(argv)
    if ":" not in a.field:
        sys.exit(f"keller.plot field: --field '{a.field}' is not FIELD:COMPONENT")
    if a.labels and len(a.labels) != len(a.branch):
        sys.exit(f"keller.plot field: {len(a.labels)} labels for {len(a.branch)} files")
    field, component = a.field.split(":", 1)
    try:
        fig, axes = plt.subplots(1, len(a.branch), figsize=(4.2 * len(a.branch), 3.8), squeeze=False)
        for k, (path, ax) in enumerate(zip(a.branch, axes[0])):
            branch = keller.results.open(path)
            parameter = branch.parameter
            stored = [s for s in branch.solutions if s.fields]
            if not stored:
                raise OutputError(f"{path}: no stored solution (/branch/fields)")
            sol = stored[-1] if a.row is None else min(stored, key=lambda s: abs(s.row - a.row))
            value, row = sol.value, sol.row
            u = field_component(path, sol, field, component)
            if sol.mesh is None:
                raise OutputError(f"{path}: no mesh (/mesh): a 1D problem's fields are tables")
            tri = sol.mesh.triangulation()  # on the deformed positions where there are some
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
        sys.exit(f"keller.plot field: {e}")
    print(f"wrote {a.output}")


if __name__ == "__main__":
    main()
