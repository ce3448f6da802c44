#!/usr/bin/python3
"""Benchmark (not a test): the 4:1 planar contraction's Oldroyd-B branch (beta = 1/9, creeping,
fully developed outflow) at De = 0, 0.25, 0.5, 0.75 by keller in log-conformation form and by the
FEniCS peer in fenics_contraction/ (stress form, DEVSS-G/SUPG), in one run, at equal accuracy.

Equal accuracy: every code's X_R, Psi_R and C at every stop within TARGET (default 1%) of the
reference values REFERENCE below (X_R and Psi_R relative to the reference; C, which changes sign
near De = 0.46, relative to the Newtonian C0 = 0.3742, the scale of C over the branch). The run

1. surveys the meshes (--meshes, default M1 M2 M3; keller and the peer alternately, mesh by mesh)
   and prints each code's deviation on each mesh, so that the choice can be checked;
2. picks for each code the coarsest surveyed mesh whose largest deviation is within the target;
3. times those two again, alternately (--repeat times: keller, peer, keller, peer, ...), so that a
   loaded machine hits both, and prints unknowns, the wall time of the whole process (meshing,
   setup, form compilation from a warm cache, output included), the time of the continuation
   (keller: the first steady state and the branch, from its output; the peer: `t_continuation`,
   its De = 0 solve included) and the ratio keller / peer of the mean wall times.

    PYTHONPATH=build/python /usr/bin/python3 runs/bench/contraction_vs_fenics.py [--meshes M1 M2 M3] [--target 1.0]
        [--repeat 2] [--keller build/bin/keller] [--work DIR] [--skip-fenics]
        [--keller-only-set KEY=VALUE ...]

The range stops at De = 0.75: keller's log form on M3 folds at De = 0.9446 (docs/contraction.md),
and the peer's finest branch (M4) was ended by its time limit before De = 1, so the reference at
De = 1 would rest on one code's M3 alone. keller's branch starts at De = 1e-4, which stands for
De = 0 (C moves by about 1e-4 over it, X_R and Psi_R by less). FEniCS needs Debian's python3-dolfin,
gmsh, python3-gmsh, python3-meshio, python3-h5py (fenics_contraction/README.md); run the peer once
before timing it, so that its forms are compiled (75 s) and cached. With --skip-fenics only keller
runs. Both children get OPENBLAS_NUM_THREADS=1 unless it is set."""

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time

from bench_support import machine
import keller

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))

STOPS = [0.0, 0.25, 0.5, 0.75]
QUANTITIES = ["X_R", "Psi_R", "C"]
MESH_F = {"M1": 1, "M2": 2, "M3": 4, "M4": 8}

# Reference values: the mean of the finest solutions of the two codes, keller's M3 (log form,
# 280,185 unknowns) and the peer's M4 (991,114 unknowns; De = 0 and 0.25-0.75 from
# fenics_contraction/README.md), with both values kept so that their spread, the reference's own
# uncertainty, is printed; see docs/contraction.md, "Cost against FEniCS", for the commands.
SOURCES = {
    # De: {"keller M3": (X_R, Psi_R, C), "peer M4": (X_R, Psi_R, C)}
    0.0: {"keller M3": (1.500728, 1.176789e-3, 0.374214), "peer M4": (1.500450, 1.176769e-3, 0.37410)},
    0.25: {"keller M3": (1.483929, 1.115989e-3, 0.182854), "peer M4": (1.48216, 1.111079e-3, 0.18242)},
    0.5: {"keller M3": (1.453740, 1.017017e-3, -0.034952), "peer M4": (1.45166, 1.008532e-3, -0.03564)},
    0.75: {"keller M3": (1.417673, 0.9083693e-3, -0.265367), "peer M4": (1.41432, 0.898366e-3, -0.26596)},
}


def reference():
    out = {}
    for de, src in SOURCES.items():
        rows = [v for v in src.values() if v[0] is not None]
        out[de] = tuple(sum(r[i] for r in rows) / len(rows) for i in range(3))
    return out


REFERENCE = reference()
C0 = REFERENCE[0.0][2]


def load():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def deviation(q, value, ref):
    """Percent deviation of quantity q from ref: relative for X_R and Psi_R, in units of C0 for C."""
    if q == "C":
        return 100.0 * (value - ref) / abs(C0)
    return 100.0 * (value / ref - 1.0)


def deviations(values):
    """{De: {q: value}} -> ({(De, q): percent deviation}, largest |deviation|, missing stops)."""
    dev = {}
    for de in STOPS:
        if de not in values:
            continue
        for i, q in enumerate(QUANTITIES):
            dev[(de, q)] = deviation(q, values[de][q], REFERENCE[de][i])
    missing = [de for de in STOPS if de not in values]
    worst = max(abs(d) for d in dev.values()) if dev and not missing else float("inf")
    return dev, worst, missing


def child_env():
    env = dict(os.environ)
    env.setdefault("OPENBLAS_NUM_THREADS", "1")
    return env


def run_keller(args, work, mesh, tag):
    scene = os.path.join(ROOT, "runs", "scenes", "flow_contraction_oldroyd_b_log.toml")
    out = os.path.join(work, "keller_%s.h5" % tag)
    stops = [s for s in STOPS if s > 0]
    cmd = [args.keller, "trace", scene, "-o", out, "--set", "parameters.Wi=1e-4",
           "--set", "continuation.upper=%g" % STOPS[-1],
           "--set", "continuation.stops=[%s]" % ",".join("%g" % s for s in stops),
           "--set", "mesh.geo_parameters.f=%d" % MESH_F[mesh]]
    for kv in args.keller_only_set:
        cmd += ["--set", kv]
    logname = os.path.join(work, "keller_%s.log" % tag)
    t0 = time.perf_counter()
    with open(logname, "w") as log:
        rc = subprocess.call(cmd, stdout=log, stderr=subprocess.STDOUT, env=child_env())
    wall = time.perf_counter() - t0
    if rc != 0:
        sys.exit("keller trace failed (exit %d); see %s" % (rc, logname))
    with open(logname) as f:
        text = f.read()
    first = re.search(r"first steady state: .*?, ([0-9.]+) s\n", text)
    branch = re.search(r"^time ([0-9.]+) s: factorisations ([0-9.]+), solves ([0-9.]+).*?Jacobians ([0-9.]+)",
                       text, re.M)
    counts = re.search(r"^(\d+) points, (\d+) rejected steps, (\d+) factorisations", text, re.M)
    cont = (float(first.group(1)) if first else 0.0) + (float(branch.group(1)) if branch else float("nan"))
    branch = keller.open(out)
    parameter, cols = branch.parameter, branch.table
    values = {}
    for k, w in enumerate(cols[parameter]):
        w = float(w)
        de = 0.0 if k == 0 and w <= 1e-4 + 1e-12 else next((s for s in stops if abs(w - s) < 1e-9), None)
        if de is not None:
            values[de] = {q: float(cols[q][k]) for q in QUANTITIES}
    unknowns = int(branch.problem["unknowns"])
    where = ""
    if branch and counts:
        where = "%s points, %s rejected, %s factorisations; factorisations %s s, solves %s s, Jacobians %s s" % (
            counts.group(1), counts.group(2), counts.group(3), branch.group(2), branch.group(3), branch.group(4))
    return dict(code="keller", mesh=mesh, unknowns=unknowns, values=values, wall=wall, cont=cont, where=where,
                command=" ".join(cmd), log=logname)


def run_fenics(args, work, mesh, tag):
    results = os.path.join(work, "fenics")
    cmd = ["/usr/bin/python3", args.peer, "solve", "--mesh", mesh, "--lu", "mumps", "--quiet", "--outflow", "fd",
           "--dde", "0.25", "--de-max", "%g" % STOPS[-1], "--results", results, "--tag", tag]
    logname = os.path.join(work, "fenics_%s.log" % tag)
    t0 = time.perf_counter()
    with open(logname, "w") as log:
        rc = subprocess.call(cmd, stdout=log, stderr=subprocess.STDOUT, cwd=work, env=child_env())
    wall = time.perf_counter() - t0
    if rc != 0:
        sys.exit("FEniCS failed (exit %d); see %s" % (rc, logname))
    with open(os.path.join(results, tag + ".json")) as f:
        r = json.load(f)
    values = {}
    for p in r["points"]:
        de = next((s for s in STOPS if abs(p["De"] - s) < 1e-9), None)
        if de is not None:
            values[de] = {q: float(p[q]) for q in QUANTITIES}
    where = "%d Newton its, %d failed steps; assembly %.1f s, LU %.1f s, observables %.1f s, setup %.1f s" % (
        r["newton_iterations"], len(r["failures"]), r["t_assembly"], r["t_solve"], r["t_observables"],
        r["t_setup_jit"])
    return dict(code="FEniCS", mesh=mesh, unknowns=r["unknowns"], values=values, wall=wall,
                cont=r["t_continuation"], where=where, command=" ".join(cmd), log=logname)


def say(r):
    dev, worst, missing = deviations(r["values"])
    print("%s %s: %s unknowns, whole process %.1f s, continuation %.1f s, largest deviation %s; %s; load %s"
          % (r["code"], r["mesh"], format(r["unknowns"], ","), r["wall"], r["cont"],
             "%.3f%%" % worst if not missing else "- (no De = %s)" % missing, r["where"], load()), flush=True)


def survey_table(runs):
    print("| code, mesh | unknowns | " + " | ".join("De = %g: X_R, Psi_R, C" % de for de in STOPS)
          + " | largest |")
    print("| --- | --- | " + " | ".join("---" for _ in STOPS) + " | --- |")
    for r in runs:
        dev, worst, _ = deviations(r["values"])
        cells = []
        for de in STOPS:
            if (de, "X_R") in dev:
                cells.append(", ".join("%+.2f" % dev[(de, q)] for q in QUANTITIES))
            else:
                cells.append("-")
        print("| %s %s | %s | %s | %s |" % (r["code"], r["mesh"], format(r["unknowns"], ","), " | ".join(cells),
                                            "%.2f%%" % worst if worst != float("inf") else "-"))


def choose(runs, code, target):
    """The coarsest surveyed mesh of `code` within the target, or None."""
    for r in runs:
        if r["code"] == code and deviations(r["values"])[1] <= target:
            return r["mesh"]
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--meshes", nargs="+", default=["M1", "M2", "M3"], choices=sorted(MESH_F),
                    help="meshes to survey, coarse to fine")
    ap.add_argument("--target", type=float, default=1.0, help="largest deviation allowed, percent")
    ap.add_argument("--repeat", type=int, default=2, help="timed keller/peer pairs after the survey")
    ap.add_argument("--keller", default=os.path.join(ROOT, "build", "bin", "keller"))
    ap.add_argument("--peer", default=os.path.join(HERE, "fenics_contraction", "contraction.py"))
    ap.add_argument("--work", default="", help="folder for the outputs (default: a temporary one)")
    ap.add_argument("--skip-fenics", action="store_true")
    ap.add_argument("--keller-only-set", nargs="*", action="extend", default=[], metavar="KEY=VALUE",
                    help="extra --set overrides for keller (solver settings); repeatable, the lists add up")
    args = ap.parse_args()
    if any(v[0] is None for src in SOURCES.values() for v in src.values()):
        print("note: some reference sources are missing; the reference is the mean of those present")
    work = args.work or tempfile.mkdtemp(prefix="contraction_vs_fenics_")
    os.makedirs(work, exist_ok=True)
    print("machine: %s" % machine())
    print("load average at start: %s (%d cores); OPENBLAS_NUM_THREADS=%s for both" % (
        load(), os.cpu_count(), child_env()["OPENBLAS_NUM_THREADS"]))
    print("\nreference (X_R, Psi_R, C) per De, from: " + ", ".join(
        "%s" % k for k in SOURCES[0.0]) + "; spread = largest half-difference, in the deviations' units")
    for de in STOPS:
        ref = REFERENCE[de]
        rows = [v for v in SOURCES[de].values() if v[0] is not None]
        spread = max(abs(deviation(q, r[i], ref[i])) for r in rows for i, q in enumerate(QUANTITIES))
        print("  De = %-4g  %.5f  %.6e  %+.5f   spread %.3f%%" % (de, ref[0], ref[1], ref[2], spread))
    print("target: every stop's X_R, Psi_R (relative) and C (in units of C0 = %.4f) within %.2f%%\n"
          % (abs(C0), args.target), flush=True)

    codes = ["keller"] + ([] if args.skip_fenics else ["FEniCS"])
    runner = {"keller": run_keller, "FEniCS": run_fenics}
    survey = []
    for mesh in args.meshes:
        for code in codes:
            r = runner[code](args, work, mesh, "%s_survey" % mesh)
            say(r)
            survey.append(r)
    print("\nDeviation from the reference, percent (X_R, Psi_R relative; C in units of C0):\n")
    survey_table(survey)
    chosen = {}
    for code in codes:
        chosen[code] = choose(survey, code, args.target)
        if chosen[code] is None:
            print("\n%s: no surveyed mesh within %.2f%%; timing its finest, %s, which is NOT equal accuracy"
                  % (code, args.target, args.meshes[-1]))
            chosen[code] = args.meshes[-1]
    print("\nequal accuracy (within %.2f%%): %s\n" % (args.target, ", ".join("%s %s" % kv for kv in chosen.items())),
          flush=True)

    timed = [r for r in survey if chosen.get(r["code"]) == r["mesh"]]
    for i in range(args.repeat):
        for code in codes:
            r = runner[code](args, work, chosen[code], "%s_timed%d" % (chosen[code], i + 1))
            say(r)
            timed.append(r)

    print("\n| code | mesh | unknowns | largest deviation | whole process s (each run) | mean | continuation s "
          "(each run) | mean |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    means = {}
    for code in codes:
        rs = [r for r in timed if r["code"] == code]
        walls = [r["wall"] for r in rs]
        conts = [r["cont"] for r in rs]
        worst = max(deviations(r["values"])[1] for r in rs)
        means[code] = (sum(walls) / len(walls), sum(conts) / len(conts))
        print("| %s | %s | %s | %.2f%% | %s | %.1f | %s | %.1f |" % (
            code, chosen[code], format(rs[0]["unknowns"], ","), worst, ", ".join("%.1f" % w for w in walls),
            means[code][0], ", ".join("%.1f" % c for c in conts), means[code][1]))
    if len(codes) == 2:
        print("\nkeller / FEniCS, whole process: %.2f; continuation: %.2f (the issue asks for at most 0.33)" % (
            means["keller"][0] / means["FEniCS"][0], means["keller"][1] / means["FEniCS"][1]))
    print("\nload average at the end: %s" % load())
    print("outputs in %s" % work)
    for code in codes:
        r = [x for x in timed if x["code"] == code][-1]
        print("%s: %s" % (code, r["command"]))


if __name__ == "__main__":
    main()
