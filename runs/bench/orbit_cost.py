"""Benchmark (not a test): what an orbit point costs against integrating 20 periods with keller
evolve on the same problem at the same accuracy (issue 37's goal: at most that).

One run, on one machine:
1. `keller trace SCENE` locates the Hopf point (not timed; the scene has [stability]);
2. `keller trace SCENE --orbit --from hopf1` traces the orbit branch; the cost of an orbit point is
   the branch's `seconds` column from its second row to its last, divided by the orbits between
   (the first two orbits, from the normal form, are reported apart: they cost more);
3. `keller evolve EVOLVE_SCENE --restart ORBITS.h5:last` integrates `--periods` periods of the last
   orbit from its u0, timed by the wall clock;
both with the same integrator and tolerances (--method, --rtol, --atol as [orbit]'s and [evolve]'s
keys),
then both again, alternating (--repeat), and the medians with their ratio.

    python3 runs/bench/orbit_cost.py runs/scenes/brusselator1d_hopf.toml runs/scenes/brusselator1d_evolve.toml \
        --set brusselator.intervals=16 --trace-set continuation.upper=5.6

Prints the machine first and last (with its load).
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_support import ROOT, machine  # noqa: E402


def run(cmd):
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"failed ({p.returncode}): {' '.join(cmd)}\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
    return time.perf_counter() - t0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene", help="a scene whose branch crosses the Hopf point, with [stability]")
    ap.add_argument("evolve_scene", help="the same problem's scene for keller evolve")
    ap.add_argument("--set", action="append", default=[], help="overrides for every run")
    ap.add_argument("--trace-set", action="append", default=[], help="overrides for the orbit branch")
    ap.add_argument("--periods", type=float, default=20.0)
    ap.add_argument("--method", default="sdirk4", help="the integrator of both ([orbit] and [evolve] method)")
    ap.add_argument("--rtol", type=float, default=1e-6, help="both runs' relative_tolerance")
    ap.add_argument("--atol", type=float, default=1e-10, help="both runs' absolute_tolerance")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--keller", default=os.environ.get("KELLER_EXE", os.path.join(ROOT, "build", "bin", "keller")))
    args = ap.parse_args(argv)
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(args.keller)), "python"))
    import keller

    print("machine:", machine(), flush=True)
    sets = [x for kv in args.set for x in ("--set", kv)]
    trace_sets = [x for kv in args.trace_set for x in ("--set", kv)]

    def accuracy(section):
        """The same integrator and tolerances for the orbits' grids and for evolve."""
        return ["--set", f'{section}.method="{args.method}"', "--set", f"{section}.relative_tolerance={args.rtol}",
                "--set", f"{section}.absolute_tolerance={args.atol}"]

    work = tempfile.mkdtemp(prefix="orbit_cost_")
    hopf = os.path.join(work, "hopf.h5")
    run([args.keller, "trace", args.scene, *sets, "-o", hopf])
    per_orbit, start, evolve = [], [], []
    for k in range(args.repeat):
        orbits = os.path.join(work, f"orbits{k}.h5")
        wall = run([args.keller, "trace", args.scene, *sets, *trace_sets, *accuracy("orbit"),
                    "--set", "stability.enabled=false",
                    "--from", f"{hopf}:hopf1", "--orbit", "-o", orbits])
        b = keller.open(orbits)
        seconds, period = b["seconds"], b["period"]
        if len(seconds) < 4:
            sys.exit("the orbit branch has fewer than 4 rows: widen its range (--trace-set continuation.upper=...)")
        per_orbit.append((seconds[-1] - seconds[1]) / (len(seconds) - 2))
        start.append(wall - (seconds[-1] - seconds[1]))
        t_end = args.periods * period[-1]
        evolve.append(run([args.keller, "evolve", args.evolve_scene, *sets, "--restart", f"{orbits}:last",
                           *accuracy("evolve"), "--set", f"evolve.t_end={t_end}",
                           "--set", 'evolve.perturbation="none"', "-o", os.path.join(work, f"evolve{k}.h5")]))
        print(f"run {k + 1}: {len(seconds) - 2} orbits at {per_orbit[-1]:.3f} s each (the run's start and first two "
              f"orbits {start[-1]:.2f} s); evolve over {args.periods:g} periods of T = {period[-1]:.6g}: "
              f"{evolve[-1]:.3f} s", flush=True)
    o, e = statistics.median(per_orbit), statistics.median(evolve)
    print(f"median: an orbit point {o:.3f} s, {args.periods:g} periods of evolve {e:.3f} s: ratio {o / e:.3f} "
          f"(goal <= 1)")
    print("machine:", machine())


if __name__ == "__main__":
    main()
