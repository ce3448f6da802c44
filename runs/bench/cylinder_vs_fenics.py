#!/usr/bin/python3
"""Benchmark (not a test): the confined-cylinder drag branch Wi = 0 .. 0.9 (Oldroyd-B, beta = 0.59,
blockage 0.5) by keller in log-conformation form and by the FEniCS implementation in
../shared/peers/fenics_cylinder (stress form, mesh M2), alternated in one run (keller, FEniCS,
keller, FEniCS, ... : --pairs of them), with the machine's load average before and after each.

The peer compiles its forms on its first run and finds them in its cache afterwards, which a
FEniCS user pays once, as the peer's mesh generation (gmsh, cached too): so the benchmark first
warms the peer (one Newton solve at Wi = 0 on its mesh, whose setup time it prints: the
compilation where the cache was cold) and times warm runs only. Both run the same OpenBLAS
kernels: the peer gets OPENBLAS_CORETYPE set to those `keller --version` names (the keller
program picks the CPU's own where OpenBLAS falls back to its generic ones, docs/performance.md),
unless the caller set it. For each run it prints unknowns,
the largest deviation from the published table for Wi <= 0.6, the deviation at 0.7, 0.8 and 0.9,
the whole process's wall time (setup, mesh building included) and the solution time (keller: its
first steady state and branch from its summary; FEniCS: its continuation from Wi = 0, setup
apart); then both ratios keller / FEniCS, whole run and solution, pair by pair and their medians.

    PYTHONPATH=build/python /usr/bin/python3 runs/bench/cylinder_vs_fenics.py [--mesh W2] [--fenics-mesh M2]
        [--pairs 2] [--keller build/bin/keller] [--peer ../shared/peers/fenics_cylinder] [--work DIR]
        [--skip-fenics] [--keller-only-set KEY=VALUE ...]

FEniCS needs Debian's python3-dolfin, gmsh, python3-gmsh, python3-meshio, python3-h5py (the
peer's README); with --skip-fenics only keller runs. keller's branch starts at Wi = 1e-4, which
stands for Wi = 0 (K differs from the Newtonian drag by O(Wi^2), 1e-6 there)."""

import argparse
import json
import os
import re
import statistics
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


def keller_solution_seconds(log_path):
    """The first steady state's and the branch's seconds from keller's log (its summary lines)."""
    with open(log_path) as f:
        text = f.read()
    first = re.search(r"^first steady state: .*, ([0-9.]+) s$", text, re.M)
    branch = re.search(r"^time ([0-9.]+) s:", text, re.M)
    if not first or not branch:
        sys.exit("keller's log %s has no first-state or time summary" % log_path)
    return float(first.group(1)) + float(branch.group(1))


def run_keller(args, work, k):
    scene = os.path.join(ROOT, "runs", "scenes", "cylinder_oldroyd_b_log.toml")
    out = os.path.join(work, "keller_cylinder_%d.h5" % k)
    if os.path.exists(out):
        os.remove(out)  # keller would continue an existing file
    cmd = [args.keller, "trace", scene, "-o", out, "--set", "parameters.Wi=1e-4", "--set", "continuation.upper=0.9",
           "--set", "continuation.stops=[%s]" % ",".join(str(s) for s in STOPS)]
    if args.mesh:
        cmd += ["--set", "mesh.name=" + args.mesh]
    for kv in args.keller_only_set:
        cmd += ["--set", kv]
    log_path = os.path.join(work, "keller_%d.log" % k)
    t0 = time.perf_counter()
    with open(log_path, "w") as log:
        rc = subprocess.call(cmd, stdout=log, stderr=subprocess.STDOUT)
    wall = time.perf_counter() - t0
    if rc != 0:
        sys.exit("keller trace failed (exit %d); see %s" % (rc, log_path))
    branch = keller.open(out)
    parameter, cols = branch.parameter, branch.table
    values = {float(w): float(k) for w, k in zip(cols[parameter], cols["K"])}
    unknowns = int(branch.problem["unknowns"])
    mesh = args.mesh or "scene default"
    return dict(name="keller " + mesh, unknowns=unknowns, dev=deviations(values), wall=wall,
                solution=keller_solution_seconds(log_path), command=" ".join(cmd))


def fenics_command(args, mesh, wi_max, results, tag):
    return ["/usr/bin/python3", os.path.join(args.peer, "cylinder.py"), "solve", "--mesh", mesh, "--lu", "mumps",
            "--wi-max", str(wi_max), "--maxit", "10", "--quiet", "--results", results, "--tag", tag]


def run_fenics(args, work, k, mesh=None, wi_max=0.9, tag=None):
    results = os.path.join(work, "fenics")
    tag = tag or "bench_%d" % k
    cmd = fenics_command(args, mesh or args.fenics_mesh, wi_max, results, tag)
    log_path = os.path.join(work, "%s.log" % tag)
    t0 = time.perf_counter()
    with open(log_path, "w") as log:
        rc = subprocess.call(cmd, stdout=log, stderr=subprocess.STDOUT, cwd=work)
    wall = time.perf_counter() - t0
    if rc != 0:
        sys.exit("FEniCS failed (exit %d); see %s" % (rc, log_path))
    with open(os.path.join(results, tag + ".json")) as f:
        r = json.load(f)
    values = {p["Wi"]: p["K_vol"] for p in r["points"]}
    return dict(name="FEniCS " + (mesh or args.fenics_mesh), unknowns=r["unknowns"], dev=deviations(values),
                wall=wall, solution=r["t_continuation"], setup=r["t_setup_jit"], command=" ".join(cmd))


def row(r):
    low = [abs(d) for w, d in r["dev"].items() if w <= 0.6 + 1e-9]
    cell = lambda w: "%+.3f%%" % r["dev"][w] if w in r["dev"] else "-"  # noqa: E731
    return "| %s | %s | within %.3f%% | %s | %s | %s | %.1f s | %.1f s |" % (
        r["name"], format(r["unknowns"], ","), max(low) if low else float("nan"), cell(0.7), cell(0.8), cell(0.9),
        r["wall"], r["solution"])


def ratios(pairs, key):
    values = [k[key] / f[key] for k, f in pairs]
    return "%s (median %.2f)" % (", ".join("%.2f" % v for v in values), statistics.median(values))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mesh", default="", help="keller mesh preset (default: the scene's)")
    ap.add_argument("--keller", default=os.path.join(ROOT, "build", "bin", "keller"))
    ap.add_argument("--peer", default=os.path.join(os.path.dirname(ROOT), "shared", "peers", "fenics_cylinder"))
    ap.add_argument("--fenics-mesh", default="M2")
    ap.add_argument("--pairs", type=int, default=2, help="keller and FEniCS runs, alternated (default 2)")
    ap.add_argument("--work", default="", help="folder for the outputs (default: a temporary one)")
    ap.add_argument("--skip-fenics", action="store_true")
    ap.add_argument("--keller-only-set", nargs="*", action="extend", default=[], metavar="KEY=VALUE",
                    help="extra --set overrides for keller (solver settings); repeatable, the lists add up")
    args = ap.parse_args()
    if args.pairs < 1:
        sys.exit("--pairs must be at least 1")
    work = args.work or tempfile.mkdtemp(prefix="cylinder_vs_fenics_")
    os.makedirs(work, exist_ok=True)
    version = subprocess.run([args.keller, "--version"], capture_output=True, text=True).stdout
    kernels = re.search(r"^BLAS: OpenBLAS, (\S+) kernels$", version, re.M)
    if kernels and "OPENBLAS_CORETYPE" not in os.environ:
        os.environ["OPENBLAS_CORETYPE"] = kernels.group(1)  # the peer's, as keller's
    print("machine: %s" % machine())
    print("BLAS kernels: keller %s, FEniCS %s" % (kernels.group(1) if kernels else "not OpenBLAS",
                                                   os.environ.get("OPENBLAS_CORETYPE", "OpenBLAS's own choice")))
    print("load average at start: %s (%d cores)" % (load(), os.cpu_count()), flush=True)
    if not args.skip_fenics:
        warm = run_fenics(args, work, 0, wi_max=0.0, tag="warm_up")
        print("FEniCS warm-up (one solve at Wi = 0): setup %.1f s of %.1f s (its form compilation where the cache was "
              "cold); load average %s" % (warm["setup"], warm["wall"], load()), flush=True)
    rows, pairs = [], []
    for k in range(args.pairs):
        kr = run_keller(args, work, k)
        rows.append(kr)
        print("keller run %d: %.1f s; load average %s" % (k + 1, kr["wall"], load()), flush=True)
        if not args.skip_fenics:
            fr = run_fenics(args, work, k)
            rows.append(fr)
            pairs.append((kr, fr))
            print("FEniCS run %d: %.1f s (setup %.1f s); load average %s" % (k + 1, fr["wall"], fr["setup"], load()),
                  flush=True)
    print()
    print("| mesh | unknowns | Wi <= 0.6 | 0.7 | 0.8 | 0.9 | whole run | solution |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for r in rows:
        print(row(r))
    if pairs:
        print("\nkeller / FEniCS time, warm, pair by pair: whole run %s; solution %s"
              % (ratios(pairs, "wall"), ratios(pairs, "solution")))
    print("\noutputs in %s" % work)
    for r in rows[:2]:
        print("%s: %s" % (r["name"], r["command"]))


if __name__ == "__main__":
    main()
