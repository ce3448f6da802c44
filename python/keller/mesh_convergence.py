"""Mesh convergence along a branch: the same scene traced on a sequence of meshes (coarse to
fine), compared at the parameter values every run located exactly (its `stops`). For each
observable it prints the values per mesh, the relative change between successive meshes (and,
with three or more, the ratio of successive changes: 2^p for order p when h is halved),
and it reports the largest parameter value up to which that change stays below --tolerance for
every observable (the branch is "mesh converged" up to there), with each run's end (for a Wi
branch: the limiting Wi, where min m1 crosses zero).

  python3 -m keller.mesh_convergence M1.h5 M2.h5 M3.h5 [--labels M1 M2 M3]
          [--observables dP dy_max gap_min max_m3] [--tolerance 0.01] [--figure conv.png] [--csv c.csv]

Reads only the branch files (HDF5, keller.open)."""

import argparse
import os
import sys

import numpy as np

import keller.results
from keller.outputs import OutputError, check_outputs, save_figure


def read_branch(path):
    """(parameter, {column: array}, status) of a branch file."""
    b = keller.results.open(path)
    return b.parameter, dict(b.table.items()), b.status


def requested_rows(cols, parameter):
    """{(parameter value, n): row} of the located requested values (kind 2); n counts earlier
    visits of the same value (a branch that turns at a fold passes a value again)."""
    out = {}
    for i, k in enumerate(cols["kind"]):
        if int(k) == 2:
            v = round(float(cols[parameter][i]), 12)
            n = sum(1 for key in out if key[0] == v)
            out[(v, n)] = i
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("files", nargs="+", help="branch files, coarse to fine")
    ap.add_argument("--labels", nargs="*", help="mesh names (default: file names)")
    ap.add_argument("--observables", nargs="*", default=["dP", "dy_max", "gap_min", "max_m3"])
    ap.add_argument("--tolerance", type=float, default=0.01, help="relative change between the two finest meshes")
    ap.add_argument("--figure", help="PNG: each observable against the parameter, one curve per mesh")
    ap.add_argument("--xmax", type=float, help="figure: largest parameter value shown")
    ap.add_argument("--csv", help="write the relative changes (one column per observable and mesh pair)")
    a = ap.parse_args(argv)
    if len(a.files) < 2:
        sys.exit("keller.mesh_convergence: needs at least two branch files")
    labels = a.labels or [os.path.splitext(os.path.basename(f))[0] for f in a.files]
    if len(labels) != len(a.files):
        sys.exit("keller.mesh_convergence: one label per file")
    try:
        check_outputs([o for o in (a.csv, a.figure) if o], a.files)
    except OutputError as e:
        sys.exit(f"keller.mesh_convergence: {e}")
    runs = [read_branch(f) for f in a.files]
    parameter = runs[0][0]
    for (p, cols, _), f in zip(runs, a.files):
        if p != parameter:
            sys.exit(f"keller.mesh_convergence: {f} is a branch in {p}, not {parameter}")
        missing = [o for o in a.observables if o not in cols]
        if missing:
            sys.exit(f"keller.mesh_convergence: {f} has no column {', '.join(missing)}")
    rows = [requested_rows(cols, parameter) for _, cols, _ in runs]
    # in the order of the branch (of the finest run)
    common = sorted(set.intersection(*[set(r) for r in rows]), key=lambda key: rows[-1][key])
    if not common:
        sys.exit("keller.mesh_convergence: no parameter value was located on every mesh (give the runs the same stops)")

    print("ends: " + "; ".join(f"{l}: {st}" for l, (_, _, st) in zip(labels, runs)))
    pairs = [f"{labels[k]}->{labels[k + 1]}" for k in range(len(labels) - 1)]
    worst = {}
    per_observable = {}
    csv_rows = {v: [v[0]] for v in common}
    csv_header = [parameter]
    for o in a.observables:
        print(f"\n{o}: values, relative change between successive meshes" +
              (", ratio of successive changes (4 for second order with h halved)" if len(labels) > 2 else ""))
        print(f"{parameter:>10} " + " ".join(f"{l:>14}" for l in labels) + " " +
              " ".join(f"{p:>12}" for p in pairs) + (f" {'ratio':>7}" if len(labels) > 2 else ""))
        csv_header += [f"{o}:{p}" for p in pairs]
        for v in common:
            vals = [cols[o][r[v]] for (_, cols, _), r in zip(runs, rows)]
            changes = [abs(vals[k + 1] - vals[k]) / max(abs(vals[k + 1]), 1e-300) for k in range(len(vals) - 1)]
            worst[v] = max(worst.get(v, 0.0), changes[-1])
            per_observable.setdefault(o, []).append((v, changes[-1]))
            csv_rows[v] += changes
            line = f"{v[0]:>10.4g} " + " ".join(f"{x:>14.7g}" for x in vals) + " " + " ".join(f"{c:>12.2e}" for c in changes)
            if len(changes) > 1:
                line += f" {changes[-2] / changes[-1]:>7.2f}" if changes[-1] > 0 else f" {'-':>7}"
            print(line)
    if a.csv:
        tmp = a.csv + ".part"
        with open(tmp, "w") as f:
            f.write(",".join(csv_header) + "\n")
            for v in common:
                f.write(",".join(repr(float(x)) for x in csv_rows[v]) + "\n")
        os.replace(tmp, a.csv)
    print(f"\nlargest {parameter} up to which {labels[-2]} -> {labels[-1]} changes by <= {a.tolerance:g}:")
    for o in a.observables:
        last = None
        for v, c in per_observable[o]:
            if c > a.tolerance:
                break
            last = v[0]
        print(f"  {o:>12}: " + (f"{last:g}" if last is not None else f"none (already {per_observable[o][0][1]:.2e} at "
                                                                       f"{parameter} = {common[0][0]:g})") +
              (" (the last common value)" if last is not None and last == common[-1][0] else ""))
    converged = None
    for v in common:
        if worst[v] <= a.tolerance:
            converged = v[0]
        else:
            break
    if converged is None:
        print(f"\nnot mesh converged at any common {parameter} (relative change {labels[-2]} -> {labels[-1]} "
              f"above {a.tolerance:g} already at {parameter} = {common[0][0]:g})")
    else:
        print(f"\nmesh converged ({labels[-2]} -> {labels[-1]} within {a.tolerance:g} in "
              f"{', '.join(a.observables)}) up to {parameter} = {converged:g}")

    if a.figure:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from keller.labels import quantity
        from keller.plot.curves import draw_branch

        fig, axes = plt.subplots(1, len(a.observables), figsize=(3.6 * len(a.observables), 3.2), squeeze=False)
        for ax, o in zip(axes[0], a.observables):
            for k, ((_, cols, _), l) in enumerate(zip(runs, labels)):
                x, y = cols[parameter], cols[o]
                keep = np.ones(len(x), bool) if a.xmax is None else x <= a.xmax
                # each mesh's branch smoothly through its tangents, its points marked
                draw_branch(ax, cols["s"][keep], x[keep], y[keep], cols.get("tangent_parameter")[keep]
                            if "tangent_parameter" in cols else None, color=f"C{k % 10}", lw=1.2, label=l)
                ax.plot(x[keep], y[keep], ".", ms=3, color=f"C{k % 10}")
            if converged is not None:
                ax.axvline(converged, color="0.6", ls=":", lw=1, label=f"converged up to {converged:g}")
            if a.xmax is not None:
                ax.set_xlim(right=a.xmax)
            ax.set_xlabel(quantity(parameter))
            ax.set_ylabel(quantity(o), fontsize=8)
            ax.grid(alpha=0.3)
        axes[0][0].legend(fontsize=7)
        fig.tight_layout()
        save_figure(fig, a.figure, a.files, dpi=130)
        print(f"wrote {a.figure}")


if __name__ == "__main__":
    sys.exit(main())
