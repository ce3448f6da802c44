"""Bifurcation diagram of branch files written by `keller trace`: any observable against the
continuation parameter, with folds, branch points, Hopf points, events, requested points and the
end marked differently. With [stability] enabled in the run, stable parts are drawn solid and
unstable parts dashed (the `unstable` column: eigenvalues with Re sigma < 0). Several files (a
branch and the branches switched from it) go into one diagram.

    python3 -m keller.plot branch BRANCH.h5 [MORE.h5 ...] [--y OBSERVABLE] [-o FIGURE.png]

Reads only the HDF5 files (keller.open; also one whose run was killed)."""

import argparse
import os
import sys

import numpy as np

import matplotlib.pyplot as plt

from keller.labels import distinguishing_labels, quantity
from keller.outputs import OutputError, check_outputs, save_figure
from keller.plot.common import columns

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


def annotate_points(ax, notes, parameter):
    """Each fold, branch point and Hopf point labelled with its parameter value once (a branch
    switched at a point starts on it: the same point), labels of points close together stacked
    instead of drawn over each other."""
    seen, placed = set(), []
    xs = [n[0] for n in notes] + list(ax.get_xlim())
    ys = [n[1] for n in notes] + list(ax.get_ylim())
    xspan, yspan = (max(xs) - min(xs)) or 1.0, (max(ys) - min(ys)) or 1.0
    for lam, val, colour in sorted(notes, key=lambda n: (n[0], n[1])):
        key = (f"{lam:.8g}", round(val / yspan, 3))
        if key in seen:
            continue
        seen.add(key)
        level = 0
        while any(abs(lam - pl) < 0.2 * xspan and abs(val - pv) < 0.06 * yspan and lv == level for pl, pv, lv in placed):
            level += 1
        placed.append((lam, val, level))
        ax.annotate(f"{parameter} = {lam:.8g}", (lam, val), textcoords="offset points", xytext=(-10, 8 + 11 * level),
                    ha="right", fontsize=8, color=colour)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("branch", nargs="+", help="branch files (HDF5) written by keller trace")
    ap.add_argument("--y", help="observable on the vertical axis (default: the first one)")
    ap.add_argument("--labels", nargs="+", help="a legend label per file (default: the scene keys that differ)")
    ap.add_argument("--title", help="title (default: the observable against the parameter)")
    ap.add_argument("-o", "--output", help="figure file (default: BRANCH with .png)")
    args = ap.parse_args(argv)
    if args.labels and len(args.labels) != len(args.branch):
        sys.exit(f"keller.plot branch: {len(args.labels)} labels for {len(args.branch)} files")

    branches = [(path, *columns(path)) for path in args.branch]
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
            sys.exit(f"keller.plot branch: {path} continues in '{par}', {args.branch[0]} in '{parameter}'")
        if y not in cols:
            sys.exit(f"keller.plot branch: no observable '{y}' in {path}; the first file has: {', '.join(observables)}")
    out = args.output or args.branch[0].rsplit(".", 1)[0] + ".png"
    try:
        check_outputs([out], args.branch)
    except OutputError as e:
        sys.exit(f"keller.plot branch: {e}")

    labels = args.labels or distinguishing_labels(args.branch, ignore={f"parameters.{parameter}"})
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    seen = set()
    styles_used = set()
    notes = []  # (parameter, value, colour) of the folds, branch points and Hopf points
    for i, (path, _, cols, status) in enumerate(branches):
        x, v, kind = cols[parameter], cols[y], cols["kind"]
        colour = "0.35" if i == 0 and len(branches) == 1 else f"C{i % 10}"
        curve = labels[i] if len(branches) > 1 else None
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
            if curve:
                ax.plot([], [], "-", color=colour, lw=1.4, label=curve)
        else:
            ax.plot(x, v, "-", color=colour, lw=1.2, zorder=1, label=curve)
        for k, (label, marker, mcolour) in MARKERS.items():
            sel = kind == k
            if sel.any():
                # one branch: a colour per kind; several: the branch's colour, the kind by the shape
                ax.scatter(x[sel], v[sel], marker=marker, color=mcolour if len(branches) == 1 else colour,
                           edgecolors="black" if len(branches) > 1 else None, linewidths=0.5,
                           s=48 if k in (5, 7) else 36, zorder=3)
                seen.add(label)
        for k, c in ((4, "tab:red"), (5, "tab:purple"), (7, "tab:cyan")):
            notes += [(lam, val, c) for lam, val in zip(x[kind == k], v[kind == k])]
    annotate_points(ax, notes, parameter)
    ax.set_xlabel(quantity(parameter))
    ax.set_ylabel(quantity(y))
    points = sum(len(b[2]["kind"]) for b in branches)
    title = args.title or (f"{y} against {parameter}: " + (os.path.basename(args.branch[0]) if len(branches) == 1
                                                             else f"{len(branches)} branches") + f", {points} points")
    ax.set_title(title, fontsize=9, wrap=True)
    # the curves first, then one entry per kind of marked point (in black where the branch's
    # colour marks it)
    handles, names = ax.get_legend_handles_labels()
    for k, (label, marker, mcolour) in MARKERS.items():
        if label in seen:
            handles.append(ax.scatter([], [], marker=marker, color=mcolour if len(branches) == 1 else "0.6",
                                      edgecolors="black" if len(branches) > 1 else None, linewidths=0.5,
                                      s=48 if k in (5, 7) else 36))
            names.append(label)
    ax.legend(handles, names, fontsize=7, loc="best")
    ax.grid(alpha=0.3)
    # why each branch ended, one line each, under the axes
    ends = [f"{labels[i] if len(branches) > 1 else 'ended'}: {b[3]}" for i, b in enumerate(branches)]
    ends = [e if len(e) < 110 else e[:107] + "..." for e in ends]
    fig.text(0.01, 0.005, "\n".join(ends), fontsize=6, color="0.4", va="bottom")
    fig.tight_layout(rect=(0, 0.012 * (len(ends) + 1), 1, 1))
    save_figure(fig, out, args.branch, dpi=150)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
