#!/usr/bin/env python3
"""Benchmark (not a test): the first steady state of every shipped collapsible-channel branch scene
on the meshes M1-M4, solved as `keller trace` solves it (Newton from the initial guess, and where
that fails, continuation from an easier state: StartSolver, docs/continuation.md). Prints for each
scene and mesh the path taken, Newton iterations, factorisations and seconds, and whether the state
was found.

  python3 runs/bench/first_states.py [--keller build/bin/keller] [--meshes M1 M2 M3 M4]
          [--only owens_gamma ...] [--set key=value ...]

Each run is `keller trace SCENE --set mesh.name=MESH --set continuation.max_steps=1` (one step of
the branch after the state, which is not counted). Prints the machine first."""

import argparse
import os
import re
import subprocess
import sys
import tempfile
import time

from bench_support import ROOT, machine, scenes


def first_state(keller, name, mesh, overrides, workdir):
    out = os.path.join(workdir, f"{name}_{mesh}.h5")
    cmd = [keller, "trace", os.path.join(ROOT, "runs", "scenes", f"collapsible_{name}.toml"), "-o", out,
           "--set", f"mesh.name=\"{mesh}\"", "--set", "continuation.max_steps=1", "--set", "output.xdmf=false"]
    for o in overrides:
        cmd += ["--set", o]
    t0 = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.monotonic() - t0
    m = re.search(r"^first steady state: (.*), (\d+) Newton iterations, (\d+) factorisations, ([0-9.]+) s$",
                  p.stdout, re.M)
    unknowns = re.search(r"; (\d+) unknowns", p.stdout)
    if os.path.exists(out):
        os.remove(out)
    if not m:
        err = (p.stderr.strip().splitlines() or ["?"])[-1]
        return {"ok": False, "path": err, "iterations": 0, "factorisations": 0, "seconds": wall,
                "unknowns": unknowns.group(1) if unknowns else "?"}
    return {"ok": True, "path": m.group(1), "iterations": int(m.group(2)), "factorisations": int(m.group(3)),
            "seconds": float(m.group(4)), "unknowns": unknowns.group(1) if unknowns else "?"}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--keller", default=os.path.join(ROOT, "build", "bin", "keller"))
    ap.add_argument("--meshes", nargs="+", default=["M1", "M2", "M3", "M4"])
    ap.add_argument("--only", nargs="+", default=None)
    ap.add_argument("--set", action="append", default=[])
    args = ap.parse_args()
    print(f"machine: {machine()}", flush=True)
    names = [n for n in scenes() if args.only is None or n in args.only]
    failed = 0
    print(f"{'scene':<24} {'mesh':<4} {'unknowns':>8} {'iters':>5} {'fact':>4} {'seconds':>8}  path")
    with tempfile.TemporaryDirectory() as work:
        for mesh in args.meshes:
            for name in names:
                r = first_state(args.keller, name, mesh, args.set, work)
                failed += not r["ok"]
                print(f"{name:<24} {mesh:<4} {r['unknowns']:>8} {r['iterations']:>5} {r['factorisations']:>4} "
                      f"{r['seconds']:>8.1f}  {r['path'] if r['ok'] else 'FAILED: ' + r['path']}", flush=True)
    print(f"{failed} failed")
    print(f"machine: {machine()}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
