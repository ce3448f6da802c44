"""What accuracy costs in time: a study's collected values on a family of meshes, with the error
of each mesh against the Richardson extrapolation of the finest ones (and against a published
value where there is one), the observed order, and the cost of each run.

    python3 -m keller.convergence STUDY/STUDY.h5 --mesh mesh.name --group fluid.formulation \\
        --observables K@0.5 K@0.9 --published K@0.5=118.83 K@0.9=117.79 \\
        --csv conv.csv --markdown conv.md --figure conv.png

Meshes are ordered by their number of unknowns n, with mesh size h = n^(-1/d) (d = --dimension,
2 by default; or h = 1/value of --resolution, a key holding intervals per unit length). For each group of tasks (the values of the --group keys) and each observable:

- observed order p from the three finest meshes: the p for which the differences of successive
  values shrink as h^p does, (q2 - q3) / (q1 - q2) = (h2^p - h3^p) / (h1^p - h2^p) with h1 > h2 > h3
  (meshes need not be refined by a constant ratio); where the differences do not fall
  monotonically there is no observed order, and --order (the formal order) is used instead;
- the Richardson extrapolation of the two finest meshes, q* = q3 + (q3 - q2) h3^p / (h2^p - h3^p);
- the relative error of every mesh against q* (and against the published value);
- the cost: unknowns, nonzeros of L + U, peak memory, seconds per linear solve, per continuation
  point and per run, as the study recorded them.

The figure: one panel per observable, the error against the run's time on log-log axes, one
curve per group."""

import argparse
import csv
import math
import os
import sys

import numpy as np

import keller.results
from keller.outputs import OutputError, check_outputs, save_figure
from keller.results import same_value

COST = [("unknowns", "unknowns"), ("nnz_lu", "nnz(L+U)"), ("peak_mb", "peak MB"),
        ("seconds_per_solve", "s/solve"), ("seconds_per_point", "s/point"), ("seconds", "s/run")]


def observed_order(h, q, formal):
    """(p, observed): the order from the three finest of meshes h (decreasing) with values q."""
    if len(q) < 3:
        return formal, False
    h1, h2, h3 = h[-3:]
    q1, q2, q3 = q[-3:]
    d1, d2 = q1 - q2, q2 - q3
    if d1 == 0 or d2 == 0 or (d1 > 0) != (d2 > 0):
        return formal, False
    target = d2 / d1

    def ratio(p):
        return (h2 ** p - h3 ** p) / (h1 ** p - h2 ** p)

    lo, hi = 0.05, 12.0  # ratio(p) falls monotonically from near 1 to 0 as p grows
    if not (ratio(hi) < target < ratio(lo)):
        return formal, False
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if ratio(mid) > target:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi), True


def richardson(h, q, p):
    """The extrapolation of the two finest meshes at order p."""
    if len(q) < 2:
        return float("nan")
    h2, h3 = h[-2:]
    q2, q3 = q[-2:]
    return q3 + (q3 - q2) * h3 ** p / (h2 ** p - h3 ** p)


def analyse(cols, mesh_key, groups, observables, published, formal, dimension, resolution=None):
    """Rows of the convergence table, one per (group, observable, mesh)."""
    done = cols["status"] == "done"
    keys = [tuple(cols[g][i] for g in groups) for i in range(len(done))]
    out = []
    for group in dict.fromkeys(keys):
        sel = [i for i in range(len(done)) if keys[i] == group and done[i]]
        sel.sort(key=lambda i: cols["unknowns"][i])
        if not sel:
            continue
        if resolution:  # a key whose value is the number of intervals per unit length
            h = 1.0 / np.array([float(cols[resolution][i]) for i in sel])
        else:
            h = np.array([cols["unknowns"][i] for i in sel], dtype=float) ** (-1.0 / dimension)
        for obs in observables:
            if obs not in cols:
                sys.exit(f"keller.convergence: no column '{obs}' in the study")
            q = np.array([cols[obs][i] for i in sel], dtype=float)
            ok = np.isfinite(q)
            hs, qs = h[ok], q[ok]
            p, observed = observed_order(list(hs), list(qs), formal)
            qx = richardson(list(hs), list(qs), p)
            for k, i in enumerate(sel):
                row = {"group": ", ".join(f"{g} = {v}" for g, v in zip(groups, group)), "observable": obs,
                       "mesh": cols[mesh_key][i], "value": q[k],
                       "error": abs(q[k] - qx) / abs(qx) if np.isfinite(q[k]) and qx else float("nan"),
                       "extrapolated": qx, "order": p, "observed": observed}
                if obs in published:
                    row["published_error"] = abs(q[k] - published[obs]) / abs(published[obs])
                for c, _ in COST:
                    row[c] = cost_of(cols, c, i)
                out.append(row)
    return out


def cost_of(cols, c, i):
    if c == "seconds_per_solve":
        return cols["solve_seconds"][i] / cols["solves"][i] if "solves" in cols and cols["solves"][i] > 0 else float("nan")
    if c == "seconds_per_point":
        return cols["seconds"][i] / cols["points"][i] if cols["points"][i] > 0 else float("nan")
    return float(cols[c][i]) if c in cols else float("nan")


def fmt(v, spec):
    return "-" if v is None or (isinstance(v, float) and not math.isfinite(v)) else format(v, spec)


def markdown(rows, published):
    head = ["group", "observable", "mesh", "value", "error vs extrapolation"]
    head += ["error vs published"] if published else []
    head += ["order"] + [name for _, name in COST]
    lines = ["| " + " | ".join(head) + " |", "|" + " --- |" * len(head)]
    for r in rows:
        cells = [r["group"], r["observable"], str(r["mesh"]), fmt(r["value"], ".8g"), fmt(r["error"], ".2e")]
        if published:
            cells.append(fmt(r.get("published_error"), ".2e"))
        cells.append(fmt(r["order"], ".2f") + ("" if r["observed"] else " (formal)"))
        cells += [fmt(r["unknowns"], ".0f"), fmt(r["nnz_lu"], ".3g"), fmt(r["peak_mb"], ".0f"),
                  fmt(r["seconds_per_solve"], ".3g"), fmt(r["seconds_per_point"], ".3g"), fmt(r["seconds"], ".3g")]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("study", help="STUDY.h5 written by keller study")
    ap.add_argument("--mesh", required=True, help="the varied key that names the mesh")
    ap.add_argument("--group", nargs="*", default=[], help="varied keys whose values make separate families")
    ap.add_argument("--where", nargs="*", default=[], metavar="KEY=VALUE",
                    help="only the tasks whose varied KEY has this VALUE (as the study table writes it)")
    ap.add_argument("--observables", nargs="+", required=True, help="collected columns (dP@0.1, end:dP, ...)")
    ap.add_argument("--published", nargs="*", default=[], help="COLUMN=VALUE: a published value to compare with")
    ap.add_argument("--order", type=float, default=2.0, help="the formal order, used where none is observed")
    ap.add_argument("--dimension", type=int, default=2, help="h = unknowns^(-1/dimension)")
    ap.add_argument("--resolution", help="instead: a varied key holding intervals per unit length, h = 1/value")
    ap.add_argument("--csv")
    ap.add_argument("--markdown")
    ap.add_argument("--figure")
    ap.add_argument("--title", help="the figure's title")
    a = ap.parse_args(argv)
    outputs = [o for o in (a.csv, a.markdown, a.figure) if o]
    try:
        check_outputs(outputs, [a.study])
    except OutputError as e:
        sys.exit(f"keller.convergence: {e}")
    published = {}
    for p in a.published:
        k, _, v = p.partition("=")
        published[k] = float(v)
    study = keller.results.Study(a.study)
    cols = dict(study.table.items())
    where = [w.partition("=") for w in a.where]
    for k in [a.mesh] + a.group + [k for k, _, _ in where]:
        if k not in cols:
            sys.exit(f"keller.convergence: the study varies no key '{k}'")
    keep = np.ones(len(cols["status"]), bool)
    for k, _, v in where:
        keep &= np.array([same_value(x, v) for x in cols[k]])
    if not keep.any():
        sys.exit(f"keller.convergence: no task has {' and '.join(a.where)}")
    cols = {c: np.asarray(v)[keep] for c, v in cols.items()}
    rows = analyse(cols, a.mesh, a.group, a.observables, published, a.order, a.dimension, a.resolution)
    table = markdown(rows, published)
    print(table, end="")
    if a.markdown:
        tmp = a.markdown + ".part"
        with open(tmp, "w") as f:
            f.write(table)
        os.replace(tmp, a.markdown)
    if a.csv:
        fields = ["group", "observable", "mesh", "value", "extrapolated", "error", "published_error", "order",
                  "observed"] + [c for c, _ in COST]
        tmp = a.csv + ".part"
        with open(tmp, "w", newline="") as f:
            # a group of several keys reads "a = 1, b = 2": the csv module quotes such cells
            w = csv.writer(f, lineterminator="\n")
            w.writerow(fields)
            for r in rows:
                w.writerow([str(r.get(c, "")) for c in fields])
        os.replace(tmp, a.csv)
    if a.figure:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        obs = list(dict.fromkeys(r["observable"] for r in rows))
        groups = list(dict.fromkeys(r["group"] for r in rows))
        ncols = min(4, len(obs))
        nrows = -(-len(obs) // ncols)
        fig, axes = plt.subplots(nrows, ncols, figsize=(3.6 * ncols, 3.0 * nrows + 0.4 + 0.2 * len(groups)),
                                 squeeze=False)
        for ax, o in zip(axes.flat, obs):
            key = "published_error" if o in published else "error"
            for k, g in enumerate(groups):
                pts = [r for r in rows if r["observable"] == o and r["group"] == g]
                t = [r["seconds"] for r in pts]
                e = [r.get(key, float("nan")) for r in pts]
                ax.loglog(t, e, "o-", ms=4, color=f"C{k % 10}", label=g or "all")
                for r in pts:
                    ax.annotate(str(r["mesh"]), (r["seconds"], r.get(key, float("nan"))), fontsize=6,
                                textcoords="offset points", xytext=(3, 3))
            ax.set_xlabel("time of the run (s)", fontsize=8)
            ax.set_ylabel("relative error, " + ("against the published value" if o in published else
                                                 "against the extrapolation"), fontsize=8)
            ax.set_title(o, fontsize=9)
            ax.grid(alpha=0.3, which="both")
        for ax in axes.flat[len(obs):]:
            ax.set_visible(False)
        handles, labels = axes.flat[0].get_legend_handles_labels()
        fig.legend(handles, labels, loc="lower center", ncol=min(2, len(groups)), fontsize=7)
        if a.title:
            fig.suptitle(a.title, fontsize=10)
        fig.tight_layout(rect=(0, (0.25 + 0.2 * len(groups)) / fig.get_figheight(), 1, 1))
        save_figure(fig, a.figure, [a.study], dpi=150)


if __name__ == "__main__":
    sys.exit(main())
