"""Rheometry of a law: branch files of the homogeneous problems `steady-shear`,
`planar-extension` and `uniaxial-extension` (written by `keller trace`) on log-log axes against
the local Weissenberg number W = lambda_0 x rate, or the rate in 1/s (--rate). Shear files give
the polymer viscosity eta_p / eta_p0 and first normal stress coefficient psi1_p = N1_p / (2
eta_p0 lambda gdot^2) (left panel); extension files give the polymer extensional viscosity
eta_e_p / eta_p0 (right panel; 4 planar and 3 uniaxial at low rate, 2 Trouton ratios). With
--data, measured points from a CSV file (a header row naming `rate` and any of the columns
eta_p, psi1_p, eta_e_p; rates in 1/s) are drawn over the law's curves, to compare a fitted law
with the measurements before using it in a flow.

    python3 -m keller.plot rheometry BRANCH.h5 [MORE.h5 ...] [--data MEASURED.csv] [--rate] [-o FIGURE.png]

Reads only the HDF5 files (keller.open)."""

import argparse
import csv
import sys

import numpy as np

import matplotlib.pyplot as plt

import keller.results
from keller.labels import distinguishing_labels
from keller.outputs import OutputError, check_outputs, save_figure

SHEAR = (("eta_p", r"$\eta_p / \eta_{p0}$", "-"), ("psi1_p", r"$\Psi_{1,p} / (2 \eta_{p0} \lambda)$", "--"))
EXTENSION = (("eta_e_p", r"$\eta_{e,p} / \eta_{p0}$", "-"),)


def read_data(path):
    """{column: array} of a CSV file with a header row."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows or "rate" not in rows[0]:
        raise OutputError(f"{path}: the first row must name the columns, one of them 'rate'")
    head = [h.strip() for h in rows[0]]
    try:
        values = np.array([[float(x) for x in r] for r in rows[1:] if r], dtype=float)
    except ValueError as e:
        raise OutputError(f"{path}: not a number: {e}") from None
    if values.ndim != 2 or values.shape[1] != len(head):
        raise OutputError(f"{path}: every row needs {len(head)} numbers")
    return {h: values[:, i] for i, h in enumerate(head)}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("branch", nargs="+", help="branch files of the rheometry problems")
    ap.add_argument("--data", help="measured points (CSV with a header: rate and eta_p, psi1_p or eta_e_p)")
    ap.add_argument("--rate", action="store_true", help="the rate in 1/s on the horizontal axis instead of W")
    ap.add_argument("-o", "--output", default="rheometry.png")
    a = ap.parse_args(argv)
    try:
        check_outputs([a.output], a.branch + ([a.data] if a.data else []))
        fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4.2))
        labels = distinguishing_labels(a.branch, ignore=("problem.type",))
        x_name = "rate" if a.rate else "Wi_local"
        used = set()
        for path, label in zip(a.branch, labels):
            branch = keller.results.open(path)
            cols = branch.table
            kind = branch.scene.get("problem", {}).get("type", "")
            if kind == "steady-shear":
                ax, curves = left, SHEAR
            elif kind in ("planar-extension", "uniaxial-extension"):
                ax, curves = right, EXTENSION
                label = f"{kind.split('-')[0]}, {label}" if len(a.branch) > 1 else kind.split("-")[0]
            else:
                raise OutputError(f"{path}: not a rheometry branch (problem.type {kind or 'unknown'})")
            used.add(ax)
            x = cols[x_name]
            colour = None  # one colour per file, a line style per quantity
            for name, tex, style in curves:
                ok = cols[name] > 0
                line = ax.loglog(x[ok], cols[name][ok], style, color=colour, label=f"{tex}: {label}")[0]
                colour = line.get_color()
        if a.data:
            d = read_data(a.data)
            if not a.rate:
                raise OutputError("--data is in rates (1/s): use it with --rate")
            for ax, curves in ((left, SHEAR), (right, EXTENSION)):
                for name, tex, _ in curves:
                    if name in d:
                        ax.loglog(d["rate"], d[name], "o", mfc="none", label=f"{tex}: {a.data}")
                        used.add(ax)
        for ax, title in ((left, "steady shear"), (right, "steady extension")):
            ax.set_xlabel("rate (1/s)" if a.rate else r"$W = \lambda_0 \times$ rate")
            ax.set_title(title)
            ax.grid(True, which="both", alpha=0.3)
            if ax in used:
                ax.legend(fontsize=7)
            else:
                ax.set_axis_off()
        fig.tight_layout()
        save_figure(fig, a.output, a.branch)
    except OutputError as e:
        print(f"keller.plot rheometry: {e}", file=sys.stderr)
        return 2
    print(f"wrote {a.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
