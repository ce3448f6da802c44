"""A collected study value against a varied key, one curve per value of another key.

    python3 -m keller.plot study STUDY/STUDY.h5 --x parameters.Gamma --y event:min_m1 \\
        --curves fluid.model --ylabel "limiting Wi" -o limiting_wi.png

Reads the table keller study writes (STUDY.h5: /study/<column>). Tasks that did not finish, or
found no value, are drawn as crosses on the x axis, with their status in the legend. The axes
are labelled by what the columns are (keller.labels.quantity: `parameters.Gamma` as its symbol,
`event:min_m1` as the branch's parameter where min m1 = 0); no title unless --title."""

import argparse
import os
import sys

import numpy as np

import matplotlib.pyplot as plt

import keller.results
from keller.labels import quantity, readable
from keller.outputs import OutputError, check_outputs, save_figure


def as_numbers(v):
    try:
        return np.array([float(x) for x in v])
    except ValueError:
        return None


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("study", help="STUDY.h5 written by keller study, or its folder")
    ap.add_argument("--x", required=True, help="the varied key on the x axis (e.g. parameters.Gamma)")
    ap.add_argument("--y", required=True, help="the collected column on the y axis (e.g. event:min_m1)")
    ap.add_argument("--curves", help="a varied key: one curve per value")
    ap.add_argument("--xlabel", help="x axis label (default: what the key is)")
    ap.add_argument("--ylabel", help="y axis label (default: what the column is)")
    ap.add_argument("--title", help="a title (default: none)")
    ap.add_argument("--logx", action="store_true")
    ap.add_argument("--logy", action="store_true")
    ap.add_argument("-o", "--output", help="figure file (default: STUDY_<y>.png)")
    a = ap.parse_args(argv)
    try:
        study = keller.results.Study(a.study)
    except (OSError, KeyError) as e:
        sys.exit(f"keller.plot study: cannot read '{a.study}': {e}")
    out = a.output or os.path.splitext(study.path)[0] + "_" + a.y.replace(":", "_").replace("@", "_at_") + ".png"
    try:
        check_outputs([out], [study.path])
    except OutputError as e:
        sys.exit(f"keller.plot study: {e}")
    cols, order = study.table, study.columns
    for key in [a.x, a.y] + ([a.curves] if a.curves else []):
        if key not in cols:
            sys.exit(f"keller.plot study: {a.study} has no column '{key}'; it has: {', '.join(order)}")
    x = as_numbers(cols[a.x])
    if x is None:
        sys.exit(f"keller.plot study: '{a.x}' does not hold numbers")
    y = np.asarray(cols[a.y], dtype=float)
    status = cols["status"]
    groups = [None] if not a.curves else list(dict.fromkeys(cols[a.curves]))
    # the branches' parameter, where the tasks share one: it names event: and @ columns
    pars = set(cols["parameter"]) if "parameter" in cols else set()
    parameter = pars.pop() if len(pars) == 1 else None

    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    marks = ["o", "s", "^", "D", "v", "P", "X", "*"]
    for i, g in enumerate(groups):
        sel = np.ones(len(x), bool) if g is None else cols[a.curves] == g
        ok = sel & np.isfinite(y) & (status == "done")
        idx = np.where(ok)[0][np.argsort(x[ok])]
        label = quantity(a.y, parameter) if g is None else readable(f"{a.curves.split('.')[-1]} = {g}")
        ax.plot(x[idx], y[idx], marks[i % len(marks)] + "-", ms=4, label=label)
        missing = sel & ~ok
        if missing.any():
            why = sorted(set(status[missing]) | ({"no value"} if (missing & (status == "done")).any() else set()))
            ax.plot(x[missing], np.zeros(missing.sum()), "x", color=ax.lines[-1].get_color(), ms=7, clip_on=False,
                    label=f"{label}: {', '.join(why)}", transform=ax.get_xaxis_transform())
    if a.logx:
        ax.set_xscale("log")
    if a.logy:
        ax.set_yscale("log")
    ax.set_xlabel(a.xlabel or quantity(a.x, parameter))
    ax.set_ylabel(a.ylabel or quantity(a.y, parameter))
    if a.title:
        ax.set_title(a.title, fontsize=10)
    ax.grid(alpha=0.3)
    if len(ax.get_legend_handles_labels()[0]) > 1:  # one curve alone is named by the axis
        ax.legend(fontsize=8)
    fig.tight_layout()
    save_figure(fig, out, [study.path], dpi=150)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
