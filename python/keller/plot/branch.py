"""Bifurcation diagram of branch files written by `keller trace`: any observable against the
continuation parameter, each branch a smooth curve through its points and their stored tangents
(keller.plot.curves), with folds, branch points, Hopf points, events, requested points and the end
marked differently. With [stability] enabled in the run, stable parts are drawn solid, unstable
parts dashed and parts not analysed dotted (the `unstable` column), a legend entry for each that
is there. Folds, branch points and Hopf points are labelled as `keller.open(...).points()` names
them (fold1, bp1, hopf1; --values: by the parameter's value), placed where they overlap no other
label and no marker. Several files (a branch and the branches switched from it) go into one
diagram.

    python3 -m keller.plot branch BRANCH.h5 [MORE.h5 ...] [--y OBSERVABLE] [--values] [--title T]
        [--footer] [-o FIGURE.png]

No title unless --title; --footer adds why each branch ended under the axes. Reads only the HDF5
files (keller.open; also one whose run was killed)."""

import argparse
import os
import sys

import numpy as np

import matplotlib.pyplot as plt

import keller.results
from keller.labels import distinguishing_labels, quantity, readable, symbol
from keller.outputs import OutputError, check_outputs, save_figure
from keller.plot.curves import STYLES, draw_branch, place_labels

MARKERS = {  # kind: (legend label, marker, colour, size)
    "start": ("start", "o", "tab:green", 30),
    "point_requested": ("requested", ".", "tab:blue", 30),
    "event": ("event", "D", "tab:orange", 26),
    "fold": ("fold", "^", "tab:red", 40),
    "bp": ("branch point", "X", "tab:purple", 48),
    "end": ("end", "s", "black", 26),
    "hopf": ("Hopf point", "*", "tab:cyan", 60),
}
KIND_CODES = {1: "start", 2: "point_requested", 3: "event", 4: "fold", 5: "bp", 6: "end", 7: "hopf"}
LABELLED = ("fold", "bp", "hopf")
STABILITY = {"unstable", "eig_residual"}
BOOKKEEPING = {"row", "kind", "s", "iterations", "step", "seconds", "det_sign", "tangent_parameter", "saved_slot"}


def observables_of(branch):
    """The columns that can go on the vertical axis (no bookkeeping, monitors, eigenvalues)."""
    return [c for c in branch.table if c not in BOOKKEEPING and c != branch.parameter and not c.startswith("monitor:")
            and c not in STABILITY and not (c.startswith("sigma") and c.endswith(("_re", "_im")))]


def labelled_points(branch, y, values=False):
    """[(parameter, observable, text, kind)] of the folds, branch points and Hopf points of a branch."""
    out = []
    for p in branch.points():
        kind = KIND_CODES.get(int(branch.table["kind"][p.index]))
        if kind in LABELLED and p.label:
            text = f"{symbol(branch.parameter)} = {p.value:.6g}" if values else p.label
            out.append((p.value, float(branch.table[y][p.index]), text, kind))
    return out


def origin_labels(paths, branches):
    """A legend label per branch from how it was started, for branches whose scenes agree (a branch
    and those switched from it): 'switched at bp1' from `--switch FILE:bp1` (a row number named by
    the label of that row in FILE where FILE is one of the plotted files), 'from fold1' from
    `--from`, else 'primary branch'. None where a command line is not stored."""
    import shlex

    out = []
    by_name = {os.path.basename(p): b for p, b in zip(paths, branches)}
    for b in branches:
        words = shlex.split(b.provenance.get("command_line", "")) if b.provenance else []
        if not words:
            return None
        text = "primary branch"
        for flag, how in (("--switch", "switched at"), ("--from", "from")):
            if flag in words[:-1]:
                source, _, point = words[words.index(flag) + 1].rpartition(":")
                src = by_name.get(os.path.basename(source))
                if src is not None and point.isdigit():
                    point = next((lab for lab, row in src.labels if row == int(point)), f"row {point}")
                text = f"{how} {point}"
        if "--switch-direction" in words[:-1] and words[words.index("--switch-direction") + 1].startswith("-"):
            text += ", other direction"
        out.append(text)
    return out if len(set(out)) == len(out) else None


def draw(ax, branches, y, labels, values=False):
    """Draws the branches into ax (curves and markers); returns (legend handles, names, points to
    label [(x, y, text, colour)])."""
    single = len(branches) == 1
    states, seen, notes = set(), set(), []
    handles, names = [], []
    for i, b in enumerate(branches):
        t = b.table
        colour = "0.3" if single else f"C{i % 10}"
        drawn, line = draw_branch(ax, t["s"], t[b.parameter], t[y], t.get("tangent_parameter"),
                                  t.get("unstable"), color=colour)
        states |= drawn
        if not single:  # the branch by its colour (its line style says its stability)
            handles.append(plt.Line2D([], [], color=colour, lw=1.6))
            names.append(labels[i])
        codes = np.asarray(t["kind"]).astype(int)
        for code, kind in KIND_CODES.items():
            sel = codes == code
            if sel.any():
                label, marker, mcolour, size = MARKERS[kind]
                ax.scatter(t[b.parameter][sel], t[y][sel], marker=marker, color=mcolour if single else colour,
                           edgecolors="black" if not single else "none", linewidths=0.5, s=size, zorder=3)
                seen.add(kind)
        for lam, val, text, kind in labelled_points(b, y, values):
            if not any(abs(lam - n[0]) <= 1e-9 * max(1.0, abs(lam)) and abs(val - n[1]) <= 1e-9 * max(1.0, abs(val))
                       for n in notes):  # a switched branch starts on its branch point: label it once
                notes.append((lam, val, text, MARKERS[kind][2] if single else colour))
    for state in ("stable", "unstable", "not analysed"):
        if state in states:
            handles.append(plt.Line2D([], [], ls=STYLES[state], color="0.3", lw=1.4))
            names.append(state)
    for kind, (label, marker, mcolour, size) in MARKERS.items():
        if kind in seen:
            handles.append(plt.Line2D([], [], ls="", marker=marker, color=mcolour if single else "0.6",
                                      markeredgecolor="black" if not single else "none", markeredgewidth=0.5,
                                      markersize=np.sqrt(size)))
            names.append(label)
    return handles, names, notes


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("branch", nargs="+", help="branch files (HDF5) written by keller trace")
    ap.add_argument("--y", help="observable on the vertical axis (default: the first one)")
    ap.add_argument("--labels", nargs="+", help="a legend label per file (default: the scene keys that differ)")
    ap.add_argument("--values", action="store_true", help="label the located points by their parameter value")
    ap.add_argument("--title", help="a title (default: none)")
    ap.add_argument("--footer", action="store_true", help="why each branch ended, under the axes")
    ap.add_argument("-o", "--output", help="figure file (default: BRANCH with .png)")
    args = ap.parse_args(argv)
    if args.labels and len(args.labels) != len(args.branch):
        sys.exit(f"keller.plot branch: {len(args.labels)} labels for {len(args.branch)} files")

    branches = [keller.results.open(path) for path in args.branch]
    parameter = branches[0].parameter
    observables = observables_of(branches[0])
    y = args.y or (observables[0] if observables else None)
    for path, b in zip(args.branch, branches):
        if b.parameter != parameter:
            sys.exit(f"keller.plot branch: {path} continues in '{b.parameter}', {args.branch[0]} in '{parameter}'")
        if y not in b.table:
            sys.exit(f"keller.plot branch: no observable '{y}' in {path}; the first file has: {', '.join(observables)}")
    out = args.output or args.branch[0].rsplit(".", 1)[0] + ".png"
    try:
        check_outputs([out], args.branch)
    except OutputError as e:
        sys.exit(f"keller.plot branch: {e}")

    labels = args.labels or distinguishing_labels(args.branch, ignore={f"parameters.{parameter}"})
    if not args.labels and len(branches) > 1 and labels == [os.path.basename(p) for p in args.branch]:
        labels = origin_labels(args.branch, branches) or labels  # the scenes agree: not by file names
    elif not args.labels:
        labels = [readable(lab) for lab in labels]  # 'Giesekus, alpha = 0.1', not 'model = giesekus, ...'
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    handles, names, notes = draw(ax, branches, y, labels, args.values)
    ax.set_xlabel(quantity(parameter))
    ax.set_ylabel(quantity(y))
    if args.title:
        ax.set_title(args.title, fontsize=10)
    if handles:
        ax.legend(handles, names, fontsize=7, loc="best", framealpha=0.9)
    ax.grid(alpha=0.3)
    ax.margins(x=0.06, y=0.08)
    bottom = 0.0
    if args.footer:
        ends = [f"{labels[i] if len(branches) > 1 else 'ended'}: {b.status}" for i, b in enumerate(branches)]
        ends = [e if len(e) < 110 else e[:107] + "..." for e in ends]
        fig.text(0.01, 0.005, "\n".join(ends), fontsize=6, color="0.4", va="bottom")
        bottom = 0.025 * (len(ends) + 1)
    fig.tight_layout(rect=(0, bottom, 1, 1))
    place_labels(ax, [(n[0], n[1]) for n in notes], [n[2] for n in notes], [n[3] for n in notes])
    save_figure(fig, out, args.branch, dpi=150)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
