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
import os
import sys

import numpy as np

import matplotlib.pyplot as plt

import keller.results
from keller.labels import FLUID_NAMES, distinguishing_labels, readable
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
        branches = [keller.results.open(path) for path in a.branch]
        kinds = [b.scene.get("problem", {}).get("type", "") for b in branches]
        for path, kind in zip(a.branch, kinds):
            if kind not in ("steady-shear", "planar-extension", "uniaxial-extension"):
                raise OutputError(f"{path}: not a rheometry branch (problem.type {kind or 'unknown'})")
        data = read_data(a.data) if a.data else {}
        if data and not a.rate:
            raise OutputError("--data is in rates (1/s): use it with --rate")
        # a panel for shear and one for extension, only where there is something to draw in it
        want_shear = "steady-shear" in kinds or any(n in data for n, _, _ in SHEAR)
        want_ext = any(k != "steady-shear" for k in kinds) or any(n in data for n, _, _ in EXTENSION)
        panels = [p for p, want in (("shear", want_shear), ("extension", want_ext)) if want]
        fig, axes = plt.subplots(1, len(panels), figsize=(5.0 * len(panels), 4.2), squeeze=False)
        ax_of = dict(zip(panels, axes[0]))
        left, right = ax_of.get("shear"), ax_of.get("extension")
        # a colour per fluid (its shear and extension files share it), a line style per quantity
        labels = distinguishing_labels(a.branch, ignore=("problem.type",))
        if labels == [os.path.basename(p) for p in a.branch]:  # one fluid: by its law's name
            labels = [FLUID_NAMES.get(b.scene.get("fluid", {}).get("model", ""), "fluid") for b in branches]
        labels = [readable(lab) for lab in labels]
        colour = {lab: f"C{k % 10}" for k, lab in enumerate(dict.fromkeys(labels))}
        x_name = "rate" if a.rate else "Wi_local"
        styles = {}  # legend entries of the line styles: {text: style}
        for branch, kind, label in zip(branches, kinds, labels):
            cols = branch.table
            curves = SHEAR if kind == "steady-shear" else EXTENSION
            ax = left if kind == "steady-shear" else right
            x = cols[x_name]
            for name, tex, style in curves:
                if kind == "uniaxial-extension":
                    style = "-."
                what = tex if kind == "steady-shear" else f"{tex}, {kind.split('-')[0]}"
                styles[what] = style
                ok = cols[name] > 0
                ax.loglog(x[ok], cols[name][ok], style, color=colour[label])
        for ax, curves in ((left, SHEAR), (right, EXTENSION)):
            for name, tex, _ in curves:
                if name in data:
                    ax.loglog(data["rate"], data[name], "o", mfc="none", color="0.2")
                    styles[f"{tex}: measured"] = "o"
        for ax, title, ylabel in ((left, "steady shear", r"$\eta_p / \eta_{p0}$, $\Psi_{1,p} / (2 \eta_{p0} \lambda)$"),
                                  (right, "steady extension", r"$\eta_{e,p} / \eta_{p0}$")):
            if ax is None:
                continue
            ax.set_xlabel("rate (1/s)" if a.rate else r"$W = \lambda_0 \dot\gamma$")
            ax.set_ylabel(ylabel)
            ax.set_title(title, fontsize=10)
            ax.grid(True, which="major", alpha=0.3)
        # under the panels: the fluids by colour, then the quantities by line style
        fluids = [plt.Line2D([], [], color=c, lw=2) for c in colour.values()]
        kinds_ = [plt.Line2D([], [], color="0.3", ls="" if st == "o" else st, marker="o" if st == "o" else None,
                             mfc="none") for st in styles.values()]
        ncol = min(3, len(colour))
        rows = -(-len(colour) // ncol)
        fig.set_figheight(4.2 + 0.2 * (rows + 1))
        height = fig.get_figheight()
        fig.legend(fluids, list(colour), loc="lower center", bbox_to_anchor=(0.5, 0.22 / height), ncol=ncol,
                   fontsize=8, frameon=False)
        fig.legend(kinds_, list(styles), loc="lower center", bbox_to_anchor=(0.5, 0.0), ncol=len(styles), fontsize=8,
                   frameon=False)
        fig.tight_layout(rect=(0, (0.3 + 0.2 * rows) / height, 1, 1))
        save_figure(fig, a.output, a.branch, dpi=150)
    except OutputError as e:
        print(f"keller.plot rheometry: {e}", file=sys.stderr)
        return 2
    print(f"wrote {a.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
