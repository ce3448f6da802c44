#!/usr/bin/python3
"""Benchmark (not a test): the confined-cylinder drag branch Wi = 0 .. 0.9 (Oldroyd-B, beta = 0.59,
blockage 0.5) by keller in log-conformation form and by the FEniCS implementation in
../shared/peers/fenics_cylinder (stress form, mesh M2), one after the other in one run, with the
machine's load average before, between and after. Prints for each: unknowns, the largest
deviation from the published table for Wi <= 0.6, the deviation at 0.7, 0.8 and 0.9, and the
wall time of the whole branch (the whole process: setup, form compilation or mesh building
included).

    PYTHONPATH=build/python /usr/bin/python3 runs/bench/cylinder_vs_fenics.py [--mesh W2] [--fenics-mesh M2]
        [--keller build/bin/keller] [--peer ../shared/peers/fenics_cylinder] [--work DIR]
        [--skip-fenics] [--keller-only-set KEY=VALUE ...]

FEniCS needs Debian's python3-dolfin, gmsh, python3-gmsh, python3-meshio, python3-h5py (the
peer's README); with --skip-fenics only keller runs. keller's branch starts at Wi = 1e-4, which
stands for Wi = 0 (K differs from the Newtonian drag by O(Wi^2), 1e-6 there)."""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

from bench_support import machine
import keller

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))

PUBLISHED = {0.0: 132.36, 0.1: 130.36, 0.2: 126.62, 0.3: 123.19, 0.4: 120.59, 0.5: 118.83, 0.6: 117.78,
             0.7: 117.32, 0.8: 117.36, 0.9: 117.79}
STOPS = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9]


def load():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def deviations(values):
    """{Wi: K} -> {Wi: percent deviation from the published table} for the Wi of the table."""
    out = {}
    for w, ref in PUBLISHED.items():
        hits = [k for x, k in values.items() if abs(x - w) < 1e-6 or (w == 0.0 and x <= 1e-4 + 1e-12)]
        if hits:
            out[w] = 100.0 * (hits[0] / ref - 1.0)
    return out


def run_keller(args, work):
    scene = os.path.join(ROOT, "runs", "scenes", "cylinder_oldroyd_b_log.toml")
    out = os.path.join(work, "keller_cylinder.h5")
    cmd = [args.keller, "trace", scene, "-o", out, "--set", "parameters.Wi=1e-4", "--set", "continuation.upper=0.9",
           "--set", "continuation.stops=[%s]" % ",".join(str(s) for s in STOPS)]
    if args.mesh:
        cmd += ["--set", "mesh.name=" + args.mesh]
    for kv in args.keller_only_set:
        cmd += ["--set", kv]
    t0 = time.perf_counter()
    with open(os.path.join(work, "keller.log"), "w") as log:
        rc = subprocess.call(cmd, stdout=log, stderr=subprocess.STDOUT)
    wall = time.perf_counter() - t0
    if rc != 0:
        sys.exit("keller trace failed (exit %d); see %s" % (rc, os.path.join(work, "keller.log")))
    branch = keller.open(out)
    parameter, cols = branch.parameter, branch.table
    values = {float(w): float(k) for w, k in zip(cols[parameter], cols["K"])}
    unknowns = int(branch.problem["unknowns"])
    mesh = args.mesh or "scene default"
    return dict(name="keller " + mesh, unknowns=unknowns, dev=deviations(values), wall=wall, command=" ".join(cmd))


def run_fenics(args, work):
    script = os.path.join(args.peer, "cylinder.py")
    results = os.path.join(work, "fenics")
    cmd = ["/usr/bin/python3", script, "solve", "--mesh", args.fenics_mesh, "--lu", "mumps", "--wi-max", "0.9",
           "--maxit", "10", "--quiet", "--results", results, "--tag", "bench"]
    t0 = time.perf_counter()
    with open(os.path.join(work, "fenics.log"), "w") as log:
        rc = subprocess.call(cmd, stdout=log, stderr=subprocess.STDOUT, cwd=work)
    wall = time.perf_counter() - t0
    if rc != 0:
        sys.exit("FEniCS failed (exit %d); see %s" % (rc, os.path.join(work, "fenics.log")))
    with open(os.path.join(results, "bench.json")) as f:
        r = json.load(f)
    values = {p["Wi"]: p["K_vol"] for p in r["points"]}
    return dict(name="FEniCS " + args.fenics_mesh, unknowns=r["unknowns"], dev=deviations(values), wall=wall,
                command=" ".join(cmd))


def row(r):
    low = [abs(d) for w, d in r["dev"].items() if w <= 0.6 + 1e-9]
    cell = lambda w: "%+.3f%%" % r["dev"][w] if w in r["dev"] else "-"  # noqa: E731
    return "| %s | %s | within %.3f%% | %s | %s | %s | %.0f s |" % (
        r["name"], format(r["unknowns"], ","), max(low) if low else float("nan"), cell(0.7), cell(0.8), cell(0.9),
        r["wall"])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mesh", default="", help="keller mesh preset (default: the scene's)")
    ap.add_argument("--keller", default=os.path.join(ROOT, "build", "bin", "keller"))
    ap.add_argument("--peer", default=os.path.join(os.path.dirname(ROOT), "shared", "peers", "fenics_cylinder"))
    ap.add_argument("--fenics-mesh", default="M2")
    ap.add_argument("--work", default="", help="folder for the outputs (default: a temporary one)")
    ap.add_argument("--skip-fenics", action="store_true")
    ap.add_argument("--keller-only-set", nargs="*", action="extend", default=[], metavar="KEY=VALUE",
                    help="extra --set overrides for keller (solver settings); repeatable, the lists add up")
    args = ap.parse_args()
    work = args.work or tempfile.mkdtemp(prefix="cylinder_vs_fenics_")
    os.makedirs(work, exist_ok=True)
    print("machine: %s" % machine())
    print("load average at start: %s (%d cores)" % (load(), os.cpu_count()), flush=True)
    rows = [run_keller(args, work)]
    print("keller done in %.1f s; load average %s" % (rows[0]["wall"], load()), flush=True)
    if not args.skip_fenics:
        rows.append(run_fenics(args, work))
        print("FEniCS done in %.1f s; load average %s" % (rows[1]["wall"], load()), flush=True)
    print()
    print("| mesh | unknowns | Wi <= 0.6 | 0.7 | 0.8 | 0.9 | whole branch |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for r in rows:
        print(row(r))
    if len(rows) == 2:
        print("\nkeller / FEniCS time: %.2f" % (rows[0]["wall"] / rows[1]["wall"]))
    print("\noutputs in %s" % work)
    for r in rows:
        print("%s: %s" % (r["name"], r["command"]))


if __name__ == "__main__":
    main()
