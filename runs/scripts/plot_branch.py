#!/usr/bin/env python3
"""Bifurcation diagram of branch files written by `keller trace`: any observable against the
continuation parameter, with folds, branch points, Hopf points, events, requested points and the
end marked differently. With [stability] enabled in the run, stable parts are drawn solid and
unstable parts dashed (the `unstable` column: eigenvalues with Re sigma < 0). Several files (a
branch and the branches switched from it) go into one diagram.

    python3 runs/scripts/plot_branch.py BRANCH.h5 [MORE.h5 ...] [--y OBSERVABLE] [-o FIGURE.png]

Reads only the HDF5 files (also one whose run was killed)."""

import argparse
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from keller_h5 import OutputError, check_outputs, read_branch, save_figure  # noqa: E402

MARKERS = {  # kind: (label, marker, colour)
    1: ("start", "o", "tab:green"),
    2: ("requested", ".", "tab:blue"),
    3: ("event", "D", "tab:orange"),
    4: ("fold", "^", "tab:red"),
    5: ("branch point", "X", "tab:purple"),
    6: ("end", "s", "black"),
    7: ("Hopf point", "*", "tab:cyan"),
}
STABILITY = {"unstable", "eig_residual"}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("branch", nargs="+", help="branch files (HDF5) written by keller trace")
    ap.add_argument("--y", help="observable on the vertical axis (default: the first one)")
    ap.add_argument("-o", "--output", help="figure file (default: BRANCH with .png)")
    args = ap.parse_args(argv)

    branches = [(path, *read_branch(path)) for path in args.branch]
    # rows in the order along the branch: a change located by bisection (stability every N points)
    # is written after rows that lie beyond it
    for _, _, cols, _ in branches:
        if "s" in cols:
            order = np.argsort(cols["s"], kind="stable")
            for c in cols:
                cols[c] = cols[c][order]
    parameter, cols0 = branches[0][1], branches[0][2]
    fixed = {"row", "kind", "s", parameter, "iterations", "step", "seconds", "det_sign", "tangent_parameter",
             "saved_slot"}
    observables = [c for c in cols0 if c not in fixed and not c.startswith("monitor:") and c not in STABILITY
                   and not (c.startswith("sigma") and (c.endswith("_re") or c.endswith("_im")))]
    y = args.y or (observables[0] if observables else None)
    for path, par, cols, _ in branches:
        if par != parameter:
            sys.exit(f"plot_branch: {path} continues in '{par}', {args.branch[0]} in '{parameter}'")
        if y not in cols:
            sys.exit(f"plot_branch: no observable '{y}' in {path}; the first file has: {', '.join(observables)}")
    out = args.output or args.branch[0].rsplit(".", 1)[0] + ".png"
    try:
        check_outputs([out], args.branch)
    except OutputError as e:
        sys.exit(f"plot_branch: {e}")

    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    seen = set()
    styles_used = set()
    for i, (path, _, cols, status) in enumerate(branches):
        x, v, kind = cols[parameter], cols[y], cols["kind"]
        colour = "0.35" if i == 0 else f"C{i % 10}"
        if "unstable" in cols:
            # one segment per pair of consecutive rows: solid where both ends are stable
            n_unst = cols["unstable"]
            for j in range(len(x) - 1):
                a, b = n_unst[j], n_unst[j + 1]
                if a != a or b != b:  # NaN: not analysed
                    style, name = ":", "not analysed"
                elif a > 0 or b > 0:
                    style, name = "--", "unstable"
                else:
                    style, name = "-", "stable"
                lab = name if name not in styles_used else None
                styles_used.add(name)
                ax.plot(x[j:j + 2], v[j:j + 2], style, color=colour, lw=1.4, zorder=1, label=lab)
        else:
            ax.plot(x, v, "-", color=colour, lw=1.2, zorder=1)
        for k, (label, marker, mcolour) in MARKERS.items():
            sel = kind == k
            if sel.any():
                ax.scatter(x[sel], v[sel], marker=marker, color=mcolour, s=48 if k in (5, 7) else 36, zorder=3,
                           label=None if label in seen else label)
                seen.add(label)
        for k, c in ((4, "tab:red"), (5, "tab:purple"), (7, "tab:cyan")):
            for lam, val in zip(x[kind == k], v[kind == k]):
                ax.annotate(f"{parameter} = {lam:.8g}", (lam, val), textcoords="offset points", xytext=(-10, 8),
                            ha="right", fontsize=8, color=c)
    status = branches[0][3]
    kind = branches[0][2]["kind"]
    ax.set_xlabel(parameter)
    ax.set_ylabel(y)
    names = ", ".join(p.split("/")[-1] for p in args.branch)
    ax.set_title(f"{names}: {sum(len(b[2]['kind']) for b in branches)} points", fontsize=9)
    ax.legend(fontsize=8, loc="best")
    ax.grid(alpha=0.3)
    fig.text(0.01, 0.01, f"ended: {status}", fontsize=7, color="0.4")
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    save_figure(fig, out, args.branch, dpi=150)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
