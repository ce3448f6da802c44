#!/usr/bin/env python3
"""Benchmark of two-parameter continuation against brute force, on the collapsible channel
(Oldroyd-B, t = 0.4, Pe = 0.04), in one run, one program after the other:

1. the Wi branch at Gamma = 4.95e-5 to its limiting Wi (the zero of min m1), and from its end
   the limiting-Wi curve in Gamma up to 6.6e-4 (the event curve, stored at the study's Gamma
   values, or with --scene-stops at its scene's), one after the other: the cost of a curve point
   against a branch point (the continuation's own time over its rows, the first state's solve and
   the output left out), against the first branch's and against all the branches' points (the
   curve crosses their whole range), and of a plain step (to an ordinary row from an ordinary
   one: no location in it) of each;
2. the Wi branches at the ten Gamma values of runs/studies/limiting_wi_gamma.toml (the one at
   4.95e-5 is that of 1.), each a whole `keller trace` from its first state, against the whole
   curve (`keller trace --from ... --curve event`, its start included), by wall clock; and the
   limiting Wi of each branch against the curve's value there.

Prints the machine, each run's time, points and factorisations, and the two ratios (goals: a curve
point at most 2 branch points; the curve at least 5 times faster than the branches).

The curve is traced --curve-runs times (default 3), spread evenly between the branches: a VM's
speed drifts by 15-30% over minutes, and one 25-second run of the curve against two minutes of
branches measures the drift as much as the code. The ratios use the curve's mean time, and each
run's time is printed.

    python3 runs/bench/bench_curves.py [--keller build/bin/keller] [--mesh M2] [--branches 10] [--scene-stops]
                                       [--curve-runs 3]

--branches N times the first N of the ten branches only (the rest are not run; the total is then
that of the N, said so in the output).
"""

import argparse
import csv
import os
import re
import subprocess
import sys
import tempfile
import time

from bench_support import machine  # (its line also states the load at the start)

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SCENES = os.path.join(ROOT, "runs", "scenes")
# the Gamma values of runs/studies/limiting_wi_gamma.toml
GAMMAS = [4.95e-5, 1.0e-4, 1.5e-4, 1.98e-4, 2.5e-4, 3.0e-4, 3.96e-4, 4.95e-4, 5.5e-4, 6.6e-4]


def load():
    return os.getloadavg()[0]


class Run:
    """One `keller trace` run: its wall time and what its summary says."""

    def __init__(self, name, cmd, log):
        self.name = name
        env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
        load0 = load()
        t0 = time.time()
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env)
        self.wall = time.time() - t0
        self.load = 0.5 * (load0 + load())
        with open(log, "w") as f:
            f.write(" ".join(cmd) + "\n" + p.stdout)
        if p.returncode != 0:
            sys.exit(f"{name}: exit {p.returncode}; see {log}")
        m = re.search(r"^(\d+) points, \d+ rejected steps, (\d+) factorisations", p.stdout, re.M)
        t = re.search(r"^time ([0-9.]+) s: factorisations ([0-9.]+)", p.stdout, re.M)
        if not m or not t:
            sys.exit(f"{name}: no summary in its output; see {log}")
        self.points, self.factorisations = int(m.group(1)), int(m.group(2))
        self.seconds, self.factor_seconds = float(t.group(1)), float(t.group(2))
        e = re.search(r"min_m1 < stop_below crossed at Wi = ([0-9.eE+-]+)", p.stdout)
        self.limiting_wi = float(e.group(1)) if e else None

    def per_point(self):
        return self.seconds / max(self.points, 1)


def table(keller, h5, work):
    """The branch table of a file as a list of rows (dicts of floats)."""
    out = os.path.join(work, os.path.basename(h5) + ".csv")
    subprocess.run([keller, "export", h5, "--csv", out], check=True, stdout=subprocess.DEVNULL)
    with open(out) as f:
        return [{k: v if k == "kind" else float(v) for k, v in r.items() if v not in ("", None)}
                for r in csv.DictReader(f)]


REGULAR = "point"  # the CSV's kind of a row an ordinary step reached (docs/output.md)


def plain_steps(rows):
    """Wall times of the steps that reached an ordinary row (not a located one) after an ordinary
    row or the start: the cost of a step alone, without locating anything."""
    return [b["seconds"] - a["seconds"] for a, b in zip(rows, rows[1:])
            if b["kind"] == REGULAR and a["kind"] in (REGULAR, "start")]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--keller", default=os.path.join(ROOT, "build", "bin", "keller"))
    ap.add_argument("--mesh", default="M2")
    ap.add_argument("--branches", type=int, default=len(GAMMAS), help="how many of the ten branches to time")
    ap.add_argument("--scene-stops", action="store_true",
                    help="the curve stored at its scene's stops (default: at the branches' Gamma values)")
    ap.add_argument("--curve-runs", type=int, default=3, help="times the curve is traced, spread between the branches")
    a = ap.parse_args()
    work = tempfile.mkdtemp(prefix="keller_bench_curves_")
    common = ["--set", f"mesh.name={a.mesh}", "--set", "output.xdmf=false"]
    branch_scene = os.path.join(SCENES, "collapsible_oldroyd_b_wi_low_gamma.toml")
    curve_scene = os.path.join(SCENES, "collapsible_oldroyd_b_wi_limit_gamma.toml")
    print(f"machine: {machine()}; files in {work}")

    def branch(i):
        out = os.path.join(work, f"wi_{i}.h5")
        cmd = [a.keller, "trace", branch_scene, *common, "--set", f"parameters.Gamma={GAMMAS[i]}", "-o", out]
        b = Run(f"Wi branch at Gamma = {GAMMAS[i]:g}", cmd, out + ".log")
        print(f"  {b.name}: {b.wall:.1f} s wall, {b.points} points, continuation {b.seconds:.1f} s "
              f"({b.per_point():.2f} s a point), limiting Wi {b.limiting_wi}, load {b.load:.2f}", flush=True)
        return b

    # the first branch, then the curve from its end (side by side), then the other branches with the
    # curve's further runs spread evenly between them
    branches = [branch(0)]
    curve_h5 = os.path.join(work, "curve.h5")
    stops = "[" + ",".join(f"{g:g}" for g in GAMMAS[1:-1]) + "]"  # the branches' Gamma values

    def trace_curve(k):
        out = curve_h5 if k == 0 else os.path.join(work, f"curve_{k}.h5")
        cmd = [a.keller, "trace", curve_scene, *common, "--from", os.path.join(work, "wi_0.h5") + ":last", "--curve",
               "event", "-o", out]
        if not a.scene_stops:
            cmd += ["--set", f"continuation.stops={stops}"]
        c = Run(f"limiting-Wi curve ({k + 1} of {a.curve_runs})", cmd, out + ".log")
        print(f"  {c.name}: {c.wall:.1f} s wall, {c.points} points, {c.factorisations} factorisations, "
              f"continuation {c.seconds:.1f} s ({c.per_point():.2f} s a point), load {c.load:.2f}", flush=True)
        return c

    runs = max(a.curve_runs, 1)
    curves = [trace_curve(0)]
    # after which branch each further run of the curve comes
    after = {round(k * (a.branches - 1) / runs) + 1: k for k in range(1, runs)}
    for i in range(1, a.branches):
        branches.append(branch(i))
        if i in after:
            curves.append(trace_curve(after[i]))
    while len(curves) < runs:  # (fewer branches than runs)
        curves.append(trace_curve(len(curves)))
    curve = curves[0]
    curve_wall = sum(c.wall for c in curves) / len(curves)
    curve_point = sum(c.per_point() for c in curves) / len(curves)

    curve_rows = table(a.keller, curve_h5, work)
    values = {r["Gamma"]: r["Wi"] for r in curve_rows}
    print("\nlimiting Wi: branch end against the curve at the same Gamma")
    for g, b in zip(GAMMAS, branches):
        near = min(values, key=lambda x: abs(x - g))
        mark = f"{values[near]:.10f}" if abs(near - g) <= 1e-9 * g else f"(nearest row Gamma = {near:g})"
        print(f"  Gamma = {g:<8g} branch {b.limiting_wi:.10f}  curve {mark}")

    b0 = branches[0]
    mean = sum(b.seconds for b in branches) / sum(b.points for b in branches)
    print("\ncost of a point (continuation time over rows):")
    print(f"  Wi branch at Gamma = 4.95e-5: {b0.per_point():.2f} s ({b0.points} points, "
          f"{b0.factorisations} factorisations, {b0.factor_seconds / max(b0.factorisations, 1):.2f} s each)")
    print(f"  the Wi branches timed, all their points: {mean:.2f} s")
    print(f"  limiting-Wi curve:            {curve_point:.2f} s (mean of {len(curves)} runs; {curve.points} points, "
          f"{curve.factorisations} factorisations, {curve.factor_seconds / max(curve.factorisations, 1):.2f} s each)")
    print(f"  ratio {curve_point / b0.per_point():.2f} to the first branch's, {curve_point / mean:.2f} to "
          f"the branches' (goal: at most 2)")
    curve_steps = plain_steps(curve_rows)
    branch_steps = [t for i in range(len(branches)) for t in plain_steps(table(a.keller, os.path.join(work, f"wi_{i}.h5"), work))]
    if curve_steps and branch_steps:
        cs, bs = sum(curve_steps) / len(curve_steps), sum(branch_steps) / len(branch_steps)
        print(f"  a plain step (to an ordinary row from an ordinary one): curve {cs:.2f} s ({len(curve_steps)} steps), "
              f"branches {bs:.2f} s ({len(branch_steps)} steps), ratio {cs / bs:.2f}")
    total = sum(b.wall for b in branches)
    told = "the ten branches" if len(branches) == len(GAMMAS) else f"the first {len(branches)} of the ten branches only"
    walls = ", ".join(f"{c.wall:.1f}" for c in curves)
    print(f"\nwhole runs (wall clock): {told}: {total:.1f} s; the curve: {curve_wall:.1f} s (mean of {walls}), "
          f"with the branch it starts from {curve_wall + b0.wall:.1f} s")
    print(f"  branches / curve = {total / curve_wall:.2f} (goal: at least 5; {total / max(c.wall for c in curves):.2f} "
          f"to {total / min(c.wall for c in curves):.2f} over the curve's runs); "
          f"branches / (curve + its first branch) = {total / (curve_wall + b0.wall):.2f}")


if __name__ == "__main__":
    main()
