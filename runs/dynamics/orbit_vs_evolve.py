"""Do the periodic orbits of `keller trace --orbit` agree with what `keller evolve` settles on?

Locates the Hopf point with `keller trace`, traces the branch of orbits born there with stops at the
given parameter values, then at each stop integrates `keller evolve` from the steady state there,
perturbed along the computed critical eigenvector, until the oscillation has settled on its limit
cycle, and measures on the time series of an observable:

- the period: the mean spacing of its upward crossings of its mean over the last periods, each
  crossing by the cubic through the four samples around it;
- the amplitude: max - min over the last period, each extreme refined by a parabola;
- the decay towards the cycle: the observable's value at the crossings of another observable's
  mean converges geometrically, by the nontrivial multiplier nearest the unit circle per period.

It prints a table of the three against the orbit branch's period, amplitude:NAME and second
multiplier, and draws the orbits' period and amplitude along the branch with evolve's marks.

    python3 runs/dynamics/orbit_vs_evolve.py runs/scenes/brusselator1d_hopf.toml \
        runs/scenes/brusselator1d_evolve.toml --observable u_mean --section v_mean \
        --stops 5.15 5.3 5.6 --set brusselator.intervals=16 -o docs/figures/orbit_vs_evolve_brusselator.png
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


def crossings(t, y, level):
    """Times where y crosses `level` upwards, each from the cubic through the four samples around
    the crossing (its root by Newton from the linear one)."""
    out = []
    for k in range(1, len(y) - 2):
        if y[k] < level <= y[k + 1]:
            ts, ys = t[k - 1:k + 3], y[k - 1:k + 3] - level
            c = np.polyfit(ts - t[k], ys, 3)
            s = (t[k + 1] - t[k]) * (-ys[1]) / (ys[2] - ys[1])
            for _ in range(20):
                s -= np.polyval(c, s) / np.polyval(np.polyder(c), s)
            out.append(t[k] + s)
    return np.array(out)


def cubic_at(t, y, times):
    """y at the given times from the cubic through the four samples around each."""
    out = []
    for tc in times:
        k = min(max(int(np.searchsorted(t, tc)) - 2, 0), len(t) - 4)
        out.append(np.polyval(np.polyfit(t[k:k + 4] - tc, y[k:k + 4], 3), 0.0))
    return np.array(out)


def extreme(t, y, largest):
    """The largest (or smallest) value of y, refined by the parabola through its neighbours."""
    k = int(np.argmax(y) if largest else np.argmin(y))
    k = min(max(k, 1), len(y) - 2)
    c = np.polyfit(t[k - 1:k + 2] - t[k], y[k - 1:k + 2], 2)
    return np.polyval(c, -c[1] / (2 * c[0])) if c[0] != 0 else y[k]


def measure(series, observable, section, periods=5):
    """Period, amplitude and contraction per period of the observable's oscillation in a time series."""
    t, y, z = series["t"], series[observable], series[section]
    last = t > t[-1] - periods * (t[-1] - t[0]) / 20
    up = crossings(t[last], y[last], 0.5 * (y[last].max() + y[last].min()))
    if len(up) < 3:
        return math.nan, math.nan, math.nan
    period = float(np.mean(np.diff(up[-periods:])))
    one = t > t[-1] - period
    amplitude = extreme(t[one], y[one], True) - extreme(t[one], y[one], False)
    # the section z = its mean upwards: y there converges by the multiplier per period
    level = 0.5 * (z[last].max() + z[last].min())
    cuts = crossings(t, z, level)
    at = cubic_at(t, y, cuts)
    settled = at[-1]
    gaps = np.abs(at - settled)[:-3]
    # the linear regime: deviations below 1e-4 of the value and well above the integrator's error
    k = np.nonzero((gaps < 1e-4 * abs(settled)) & (gaps > 1e-8 * abs(settled)))[0]
    contraction = math.exp(np.polyfit(k, np.log(gaps[k]), 1)[0]) if len(k) >= 3 else math.nan
    return period, amplitude, contraction


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("trace_scene", help="a scene whose branch crosses the Hopf point, with [stability]")
    ap.add_argument("evolve_scene", help="the same problem's scene for keller evolve")
    ap.add_argument("--observable", required=True, help="the observable whose period and amplitude are compared")
    ap.add_argument("--section", required=True, help="another observable whose mean is the Poincare section")
    ap.add_argument("--stops", type=float, nargs="+", required=True, help="parameter values to compare at")
    ap.add_argument("--periods", type=float, default=60.0, help="evolve over this many periods (default 60)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="scene overrides for every run")
    ap.add_argument("--evolve-set", action="append", default=[], metavar="KEY=VALUE",
                    help="overrides for the evolve runs alone (default: SDIRK4 at rtol 1e-9)")
    ap.add_argument("--orbit-set", action="append", default=["orbit.relative_tolerance=1e-8"], metavar="KEY=VALUE",
                    help="overrides for the orbit branch alone (default: rtol 1e-8)")
    ap.add_argument("--work", default="orbit_vs_evolve", help="folder for the runs (reused when there)")
    ap.add_argument("-o", "--output", default="orbit_vs_evolve.png", help="the figure")
    args = ap.parse_args(argv)

    import keller
    from keller.outputs import check_outputs, save_figure

    check_outputs([args.output])
    os.makedirs(args.work, exist_ok=True)
    overrides = parse_sets(args.set)
    path = os.path.join(args.work, "hopf.h5")
    branch = keller.open(path) if os.path.exists(path) else keller.trace(args.trace_scene, path, set=overrides,
                                                                          verbose=False)
    hopfs = branch.points("hopf")
    if not hopfs:
        sys.exit(f"{branch.path}: no Hopf point on the branch")
    nf = hopfs[0].normal_form
    side = int(nf["side"])
    par = branch.parameter
    path = os.path.join(args.work, "orbits.h5")
    bound = "upper" if side > 0 else "lower"
    far = max(args.stops) + 0.05 if side > 0 else min(args.stops) - 0.05
    orbits = keller.open(path) if os.path.exists(path) else keller.trace(
        args.trace_scene, path, orbit_from=(branch, "hopf1"), verbose=False,
        set={**overrides, "stability.enabled": False, "continuation.stops": list(args.stops),
             f"continuation.{bound}": far, **parse_sets(args.orbit_set)})
    stops = orbits.points("stop")
    rows = []
    for p in stops:
        lam = p.value
        period = p["period"]
        sets = {**overrides, f"parameters.{par}": lam, "evolve.t_end": args.periods * period,
                "evolve.perturbation": "computed", "evolve.shift_im": 2 * math.pi / period, "evolve.amplitude": 1e-2,
                "evolve.method": "sdirk4", "evolve.relative_tolerance": 1e-9, "evolve.absolute_tolerance": 1e-12,
                "evolve.max_step": period / 100, "evolve.save_every": 100000, "evolve.print_every": 100000,
                # a small problem's thousands of solves: UMFPACK's per call cost is MUMPS's fraction (the
                # orbit branch chooses it itself, continuation/orbits/ShootingMap.hpp)
                "linear_solver.backend": "umfpack"}
        sets.update(parse_sets(args.evolve_set))
        epath = os.path.join(args.work, f"evolve_{lam:g}.h5")
        series = keller.open(epath) if os.path.exists(epath) else keller.evolve(args.evolve_scene, epath, set=sets,
                                                                                 verbose=False)
        T, A, mu = measure(series, args.observable, args.section)
        mus = [complex(p[f"mu{k}_re"], p[f"mu{k}_im"]) for k in range(2, 10) if f"mu{k}_re" in p.values]
        mu2 = max(mus, key=abs) if mus else complex(math.nan)
        rows.append((lam, period, T, p[f"amplitude:{args.observable}"], A, abs(mu2), mu))
    print(f"{par:>8} {'T orbit':>14} {'T evolve':>14} {'rel':>9} {'A orbit':>11} {'A evolve':>11} {'rel':>9} "
          f"{'|mu2|':>9} {'decay':>9}")
    for lam, T1, T2, A1, A2, m1, m2 in rows:
        print(f"{lam:8.4g} {T1:14.10g} {T2:14.10g} {T2 / T1 - 1:9.2e} {A1:11.7g} {A2:11.7g} {A2 / A1 - 1:9.2e} "
              f"{m1:9.4g} {m2:9.4g}")

    import matplotlib
    if __name__ == "__main__":
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(7.5, 3.2), constrained_layout=True)
    lam = orbits[par]
    ax1.plot(lam, orbits["period"], "-", color="0.3", label="orbit branch")
    ax1.plot([r[0] for r in rows], [r[2] for r in rows], "o", mfc="none", label="keller evolve")
    ax1.set_xlabel(par)
    ax1.set_ylabel("period")
    ax1.legend(frameon=False)
    ax2.plot(lam, orbits[f"amplitude:{args.observable}"], "-", color="0.3", label="orbit branch")
    ax2.plot([r[0] for r in rows], [r[4] for r in rows], "o", mfc="none", label="keller evolve")
    ax2.set_xlabel(par)
    ax2.set_ylabel(f"amplitude of {args.observable} (max - min)")
    save_figure(fig, args.output, dpi=200)
    print(f"wrote {args.output}")
    return rows


if __name__ == "__main__":
    main()
