#!/usr/bin/env python3
"""Bifurcation diagram of a branch file written by `keller trace`: any observable against the
continuation parameter, with folds, events, branch points, requested points and the end marked.

    python3 runs/scripts/plot_branch.py BRANCH.h5 [--y OBSERVABLE] [-o FIGURE.png]

Reads only the HDF5 file (also one whose run was killed)."""

import argparse
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from keller_h5 import read_branch  # noqa: E402

MARKERS = {  # kind: (label, marker, colour)
    1: ("start", "o", "tab:green"),
    2: ("requested", ".", "tab:blue"),
    3: ("event", "D", "tab:orange"),
    4: ("fold", "^", "tab:red"),
    5: ("branch point", "X", "tab:purple"),
    6: ("end", "s", "black"),
}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("branch", help="branch file (HDF5) written by keller trace")
    ap.add_argument("--y", help="observable on the vertical axis (default: the first one)")
    ap.add_argument("-o", "--output", help="figure file (default: BRANCH with .png)")
    args = ap.parse_args(argv)

    parameter, cols, status = read_branch(args.branch)
    fixed = {"row", "kind", "s", parameter, "iterations", "step", "seconds", "det_sign", "tangent_parameter",
             "saved_slot"}
    observables = [c for c in cols if c not in fixed and not c.startswith("monitor:")]
    y = args.y or (observables[0] if observables else None)
    if y not in cols:
        sys.exit(f"plot_branch: no observable '{y}'; the file has: {', '.join(observables)}")
    out = args.output or args.branch.rsplit(".", 1)[0] + ".png"

    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.plot(cols[parameter], cols[y], "-", color="0.35", lw=1.2, zorder=1)
    kind = cols["kind"]
    for k, (label, marker, colour) in MARKERS.items():
        sel = kind == k
        if sel.any():
            ax.scatter(cols[parameter][sel], cols[y][sel], marker=marker, color=colour, s=36, zorder=3, label=label)
    for lam, val in zip(cols[parameter][kind == 4], cols[y][kind == 4]):
        ax.annotate(f"{parameter} = {lam:.8g}", (lam, val), textcoords="offset points", xytext=(-10, 8), ha="right",
                    fontsize=8, color="tab:red")
    ax.set_xlabel(parameter)
    ax.set_ylabel(y)
    ax.set_title(f"{args.branch.split('/')[-1]}: {len(kind)} points", fontsize=9)
    ax.legend(fontsize=8, loc="best")
    ax.grid(alpha=0.3)
    fig.text(0.01, 0.01, f"ended: {status}", fontsize=7, color="0.4")
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    fig.savefig(out, dpi=150)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
