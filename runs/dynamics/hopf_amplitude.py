"""Does the oscillation past a Hopf point saturate at the amplitude its normal form predicts?

Locates the Hopf point with `keller trace` (its normal form: l1, the side where the orbits are, and
each observable's amplitude per sqrt(|lambda - lambda0|), docs/normal_forms.md), then for each
distance d integrates `keller evolve` at lambda0 + side d from the steady state there (which the
evolve scene's solve reaches) plus the computed critical eigenvector (its largest entry 0.3 of the predicted orbit's), and measures the observable's amplitude, (max - min) / 2 over the
last periods. For a supercritical point the measured amplitude agrees with the prediction to O(d)
(the normal form's next order); for a subcritical one the oscillation grows past it.

    python3 runs/dynamics/hopf_amplitude.py runs/scenes/brusselator1d_hopf.toml \
        runs/scenes/brusselator1d_evolve.toml --observable v_mean --distances 0.005 0.01 0.02 0.04 \
        -o docs/figures/hopf_amplitude_brusselator.png

Prints a table (distance, time integrated, measured, predicted, relative difference) and draws the
amplitudes against the distance with the prediction, and the relative difference with a slope-1 line.
"""
import argparse
import math
import os
import sys

import numpy as np


def parse_sets(texts):
    """KEY=VALUE overrides (VALUE in TOML, as keller's --set takes it) as {key: value}."""
    import tomllib
    out = {}
    for kv in texts:
        key, value = kv.split("=", 1)
        out[key.strip()] = tomllib.loads(f"v = {value}")["v"]
    return out


def measure(series, observable, period, periods=4):
    """(max - min) / 2 of an observable over its last `periods` periods, and the same over the
    `periods` before them (how far it still drifts)."""
    t, y = series["t"], series[observable]
    end = t[-1]
    last = t > end - periods * period
    before = (t > end - 2 * periods * period) & ~last
    amp = lambda m: 0.5 * (y[m].max() - y[m].min()) if m.any() else math.nan
    return amp(last), amp(before)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("trace_scene", help="a scene whose branch crosses the Hopf point, with [stability]")
    ap.add_argument("evolve_scene", help="the same problem's scene for keller evolve")
    ap.add_argument("--observable", required=True, help="the observable whose amplitude is compared")
    ap.add_argument("--distances", type=float, nargs="+", default=[0.005, 0.01, 0.02, 0.04],
                    help="distances past the point, in the parameter's units")
    ap.add_argument("--growths", type=float, default=8.0,
                    help="integrate over this many growth times 1 / (g' d) (default 8)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="scene overrides for both runs (e.g. mesh.name='\"M2\"')")
    ap.add_argument("--trace-set", action="append", default=[], metavar="KEY=VALUE",
                    help="overrides for the trace alone (its range)")
    ap.add_argument("--evolve-set", action="append", default=[], metavar="KEY=VALUE",
                    help="overrides for the evolve runs alone (tolerances)")
    ap.add_argument("--work", default="hopf_amplitude", help="folder for the runs (reused when there)")
    ap.add_argument("-o", "--output", default="hopf_amplitude.png", help="the figure")
    args = ap.parse_args(argv)

    import keller
    from keller.outputs import check_outputs, save_figure

    check_outputs([args.output])
    os.makedirs(args.work, exist_ok=True)
    overrides = parse_sets(args.set)
    branch_path = os.path.join(args.work, "hopf.h5")
    branch = keller.open(branch_path) if os.path.exists(branch_path) else keller.trace(
        args.trace_scene, branch_path, set={**overrides, **parse_sets(args.trace_set)})
    hopfs = branch.points("hopf")
    if not hopfs or hopfs[0].normal_form is None:
        sys.exit(f"{branch.path}: no Hopf point with a normal form on the branch")
    point = hopfs[0]
    nf = point.normal_form
    column = f"amplitude:{args.observable}"
    if column not in nf:
        sys.exit(f"no observable '{args.observable}'; the normal form has {[c for c in nf if c.startswith('amplitude:')]}")
    g, side, lam0 = nf["growth_rate_derivative"], int(nf["side"]), point.value
    coefficient, period = nf[column], nf["period"]
    scale = max(float(np.abs(point.solution.u).max()), 1.0) if point.solution is not None else 1.0
    print(f"{nf['type']} at {branch.parameter} = {lam0:.10g}: l1 = {nf['l1']:.6g}, period {period:.6g}, "
          f"{args.observable} amplitude {coefficient:.6g} sqrt(|d|) for {'larger' if side > 0 else 'smaller'} "
          f"{branch.parameter}")
    rows = []
    for d in args.distances:
        lam = lam0 + side * d
        predicted = coefficient * math.sqrt(d)
        t_end = args.growths / (abs(g) * d)
        sets = dict(overrides)
        sets.update(parse_sets(args.evolve_set))
        sets.update({f"parameters.{branch.parameter}": lam, "evolve.t_end": t_end, "evolve.perturbation": "computed",
                     "evolve.shift_im": 2 * math.pi / period,
                     # the perturbation's largest entry, which keller evolve takes over max(|u|_inf, 1)
                     "evolve.amplitude": 0.3 * nf["amplitude_coefficient"] * math.sqrt(d) / scale})
        path = os.path.join(args.work, f"evolve_{d:g}.h5")
        series = keller.open(path) if os.path.exists(path) else keller.evolve(
            args.evolve_scene, path, set=sets, verbose=False)
        measured, before = measure(series, args.observable, period)
        rows.append((d, t_end, measured, predicted, measured / predicted - 1.0, before / predicted - 1.0))
    print(f"{'distance':>10} {'t_end':>10} {'measured':>12} {'predicted':>12} {'difference':>11} {'(earlier)':>10}")
    for d, t_end, m, p, r, rb in rows:
        print(f"{d:10.4g} {t_end:10.4g} {m:12.6g} {p:12.6g} {r:11.3%} {rb:10.3%}")

    import matplotlib
    if __name__ == "__main__":
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    d = np.array([r[0] for r in rows])
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(7.5, 3.2), constrained_layout=True)
    fine = np.geomspace(d.min() / 1.5, d.max() * 1.5, 50)
    ax1.plot(fine, coefficient * np.sqrt(fine), "-", color="0.4", label="normal form")
    ax1.plot(d, [r[2] for r in rows], "o", label="keller evolve")
    ax1.set_xscale("log")
    ax1.set_yscale("log")
    ax1.set_xlabel(f"distance past the Hopf point, |{branch.parameter} - {branch.parameter}$_H$|")
    ax1.set_ylabel(f"amplitude of {args.observable}")
    ax1.legend(frameon=False)
    rel = np.abs([r[4] for r in rows])
    ax2.plot(d, rel, "o", label="|measured / predicted - 1|")
    ax2.plot(fine, rel[-1] * fine / d[-1], "--", color="0.4", label="slope 1")
    ax2.set_xscale("log")
    ax2.set_yscale("log")
    ax2.set_xlabel(f"|{branch.parameter} - {branch.parameter}$_H$|")
    ax2.legend(frameon=False)
    save_figure(fig, args.output, dpi=200)
    print(f"wrote {args.output}")
    return rows


if __name__ == "__main__":
    main()
