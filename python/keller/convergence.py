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

Outside the asymptotic range. Richardson's extrapolation, and an error read against it, hold only
where every mesh is in the asymptotic range, where the error falls as C h^p with one p. So the
observed order is computed from every three successive meshes (p_1 from meshes 1-3, p_2 from 2-4,
...), and the sequence counts as settled when:

- it has at least three meshes with values (with fewer there is no order at all: not settled);
- every triple has an observed order (differences falling monotonically);
- with three meshes, the one observed order is within --order-tolerance (0.25 by default) of the
  formal order (there is no second order to compare it with, and the formal order is what the
  method promises); with four or more, every two successive observed orders are within
  --order-tolerance of each other (an order still moving, 1.2 then 1.9 then 2.0, says the coarse
  meshes were not yet asymptotic, and nothing shows the finest pair is).

0.25 is a quarter of an order: well above the scatter of the orders of a smooth sequence that is
asymptotic (the 1e-2 of rounding in the differences of a second-order sequence moves its
observed order by about 0.02), well below the change of a pre-asymptotic one. A sequence that is
not settled is warned about on stderr, marked "(not settled)" in the printed and Markdown tables
(the column `settled` of the CSV), and, with --mark-unsettled only, drawn dashed in the figure.

The figure: one panel per observable, the error against the run's time on log-log axes, one
curve per group (a marker per mesh, its key with the groups' legend in a panel left free by the
grid, or under the panels)."""

import argparse
import csv
import math
import os
import sys

import numpy as np

import keller.results
from keller.outputs import OutputError, check_outputs
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


ORDER_TOLERANCE = 0.25


def settled_order(h, q, formal, tolerance=ORDER_TOLERANCE):
    """(settled, orders, why): the observed orders of every three successive meshes (h decreasing)
    and whether the sequence is in the asymptotic range by the rule of the module's doc; `why`
    says why not (empty when settled)."""
    h, q = list(h), list(q)
    if len(q) < 3:
        return False, [], f"{len(q)} meshes with a value: fewer than 3 give no order"
    orders = []
    for k in range(len(q) - 2):
        p, observed = observed_order(h[k:k + 3], q[k:k + 3], formal)
        if not observed:
            return False, orders, f"no observed order from meshes {k + 1}-{k + 3} (the differences do not fall)"
        orders.append(p)
    if len(orders) == 1:
        if abs(orders[0] - formal) > tolerance:
            return False, orders, (f"the observed order {orders[0]:.2f} of 3 meshes is not the formal {formal:g} "
                                   f"(within {tolerance:g})")
        return True, orders, ""
    jumps = [abs(b - a) for a, b in zip(orders, orders[1:])]
    if max(jumps) > tolerance:
        return False, orders, ("the observed orders " + ", ".join(f"{p:.2f}" for p in orders)
                               + f" differ by more than {tolerance:g}")
    return True, orders, ""


def richardson(h, q, p):
    """The extrapolation of the two finest meshes at order p."""
    if len(q) < 2:
        return float("nan")
    h2, h3 = h[-2:]
    q2, q3 = q[-2:]
    return q3 + (q3 - q2) * h3 ** p / (h2 ** p - h3 ** p)


def analyse(cols, mesh_key, groups, observables, published, formal, dimension, resolution=None,
            tolerance=ORDER_TOLERANCE):
    """Rows of the convergence table, one per (group, observable, mesh), each with whether its
    sequence is `settled` (settled_order) and, where not, `why`."""
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
            settled, orders, why = settled_order(hs, qs, formal, tolerance)
            qx = richardson(list(hs), list(qs), p)
            for k, i in enumerate(sel):
                row = {"group": ", ".join(f"{g} = {v}" for g, v in zip(groups, group)), "observable": obs,
                       "mesh": cols[mesh_key][i], "value": q[k],
                       "error": abs(q[k] - qx) / abs(qx) if np.isfinite(q[k]) and qx else float("nan"),
                       "extrapolated": qx, "order": p, "observed": observed, "settled": settled, "why": why,
                       "group_values": dict(zip(groups, group))}
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
        cells.append(fmt(r["order"], ".2f") + ("" if r["observed"] else " (formal)")
                     + ("" if r["settled"] else " (not settled)"))
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
    ap.add_argument("--title", help="the figure's title (default: none)")
    ap.add_argument("--order-tolerance", type=float, default=ORDER_TOLERANCE,
                    help="successive observed orders further apart than this: not in the asymptotic range")
    ap.add_argument("--mark-unsettled", action="store_true",
                    help="figure: draw dashed the sequences not in the asymptotic range")
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
    rows = analyse(cols, a.mesh, a.group, a.observables, published, a.order, a.dimension, a.resolution,
                   a.order_tolerance)
    warned = set()
    for r in rows:
        if not r["settled"] and (r["group"], r["observable"]) not in warned:
            warned.add((r["group"], r["observable"]))
            print(f"keller.convergence: warning: {r['observable']}" + (f" ({r['group']})" if r["group"] else "")
                  + f" is outside the asymptotic range: {r['why']}", file=sys.stderr)
    table = markdown(rows, published)
    print(table, end="")
    if a.markdown:
        tmp = a.markdown + ".part"
        with open(tmp, "w") as f:
            f.write(table)
        os.replace(tmp, a.markdown)
    if a.csv:
        fields = ["group", "observable", "mesh", "value", "extrapolated", "error", "published_error", "order",
                  "observed", "settled"] + [c for c, _ in COST]
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

        matplotlib.use("Agg")  # a file: no display
        from keller.plot.convergence_figure import draw

        pars = set(cols["parameter"]) if "parameter" in cols else set()
        draw(rows, published, a.figure, [a.study], title=a.title, mark_unsettled=a.mark_unsettled,
             parameter=pars.pop() if len(pars) == 1 else None)
    return 0

if __name__ == "__main__":
    sys.exit(main())
