#!/usr/bin/env python3
"""Benchmark (not a test): the 14 collapsible-channel branches of the shipped scenes, each traced
by `keller trace` as a user would, one after the other, with a table of what each costs and where
it ends: rows after the start, factorisations (continuation only; the first steady state's Newton
factorisations are printed apart), rejected steps, wall time of the trace and of the whole run,
the located values (requested values, events, ends) and the end of the branch.

  PYTHONPATH=build/python python3 runs/bench/collapsible_branches.py [--keller build/bin/keller] [--set key=value ...]
          [--config NAME key=value ... --config NAME2 ...] [--only owens_gamma ...]
          [--save FILE.json] [--compare FILE.json] [--relative 1e-8]

--config runs every branch once per named configuration (extra --set overrides, and
keller=PATH for another binary, e.g. an older build), alternating configurations branch by branch
so that all see the same machine load: ratios between them are measured in one run. --compare checks the located and end values of every branch against a saved
table to --relative (default 1e-8) and the total of factorisations against it.
Prints the machine (CPU model, cores, memory, OPENBLAS_NUM_THREADS, load average) first."""

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time

from bench_support import ROOT, machine, scenes
from keller import open as open_result

# the located kinds of a branch table, by the names the saved JSON tables use
KINDS = {2: "requested", 3: "event", 4: "fold", 5: "branch point", 6: "end", 7: "hopf"}


def trace(keller, name, overrides, workdir):
    # a configuration may name its own binary ("keller=PATH", e.g. an older build to compare with)
    for o in overrides:
        if o.startswith("keller="):
            keller = o[len("keller="):]
    overrides = [o for o in overrides if not o.startswith("keller=")]
    out = os.path.join(workdir, name + ".h5")
    cmd = [keller, "trace", os.path.join(ROOT, "runs", "scenes", f"collapsible_{name}.toml"), "-o", out,
           "--set", "output.xdmf=false"]
    for o in overrides:
        cmd += ["--set", o]
    t0 = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.monotonic() - t0
    if p.returncode not in (0, 1):
        raise RuntimeError(f"{name}: exit {p.returncode}\n{p.stderr}\n{p.stdout[-3000:]}")
    text = p.stdout
    m = re.search(r"(\d+) points, (\d+) rejected steps, (\d+) factorisations", text)
    probes = re.search(r"(\d+) of them branch-point probes", text)
    t = re.search(r"^time ([0-9.]+) s: factorisations ([0-9.]+), solves ([0-9.]+) \((\d+)\)", text, re.M)
    newton_fact = None
    nf = re.search(r"first steady state: .*?(\d+) factorisations", text)
    if nf:
        newton_fact = int(nf.group(1))
    branch = open_result(out)
    parameter, cols, status = branch.parameter, branch.table, branch.status
    located = []
    for i, k in enumerate(cols["kind"]):
        if int(k) in KINDS:
            located.append([KINDS[int(k)], float(cols[parameter][i])])
    last = {c: float(cols[c][-1]) for c in cols if c in (parameter, "dP", "dy_max", "gap_min", "min_m1")}
    os.remove(out)
    return {
        "rows": int(m.group(1)) - 1,
        "rejected": int(m.group(2)),
        "factorisations": int(m.group(3)),
        "probes": int(probes.group(1)) if probes else 0,
        "trace_seconds": float(t.group(1)),
        "factor_seconds": float(t.group(2)),
        "solve_seconds": float(t.group(3)),
        "solves": int(t.group(4)),
        "run_seconds": wall,
        "start_factorisations": newton_fact,
        "start_path": "homotopy" if "homotopy" in text else "newton",
        "located": located,
        "end": last,
        "status": status,
        "exit": p.returncode,
    }


def print_table(label, results):
    print(f"\n{label}")
    print(f"{'branch':<26} {'rows':>4} {'fact':>4} {'prb':>3} {'rej':>3} {'f/row':>5} {'trace s':>8} {'run s':>7}  "
          "located ... | end")
    tot = {"rows": 0, "factorisations": 0, "probes": 0, "rejected": 0, "trace_seconds": 0.0, "run_seconds": 0.0}
    for name, r in results.items():
        for k in tot:
            tot[k] += r.get(k, 0)
        loc = ", ".join(f"{kind[0]}{v:.10g}" for kind, v in r["located"])
        end = " ".join(f"{k}={v:.10g}" for k, v in r["end"].items())
        print(f"{name:<26} {r['rows']:>4} {r['factorisations']:>4} {r.get('probes', 0):>3} {r['rejected']:>3} "
              f"{r['factorisations'] / max(r['rows'], 1):>5.2f} {r['trace_seconds']:>8.2f} {r['run_seconds']:>7.2f}  "
              f"{loc} | {end}")
    print(f"{'total':<26} {tot['rows']:>4} {tot['factorisations']:>4} {tot['probes']:>3} {tot['rejected']:>3} "
          f"{tot['factorisations'] / max(tot['rows'], 1):>5.2f} {tot['trace_seconds']:>8.2f} {tot['run_seconds']:>7.2f}")
    return tot


def compare(results, reference, relative):
    bad = 0
    for name, r in results.items():
        if name not in reference:
            continue
        ref = reference[name]
        a = [v for _, v in r["located"]]
        b = [v for _, v in ref["located"]]
        if [k for k, _ in r["located"]] != [k for k, _ in ref["located"]]:
            print(f"  {name}: located kinds differ: {r['located']} vs {ref['located']}")
            bad += 1
            continue
        for x, y in zip(a, b):
            if abs(x - y) > relative * max(abs(y), 1e-300):
                print(f"  {name}: located {x:.12g} vs reference {y:.12g} (rel {abs(x - y) / abs(y):.2e})")
                bad += 1
        for k, y in ref["end"].items():
            x = r["end"].get(k)
            # (min_m1 ends at its located zero: a value of rounding size, compared absolutely)
            absolute = 1e-10 if k == "min_m1" else 1e-12
            if x is None or abs(x - y) > max(relative * abs(y), absolute):
                print(f"  {name}: end {k} = {x} vs reference {y:.12g}")
                bad += 1
    ft = sum(r["factorisations"] for r in results.values())
    fr = sum(reference[n]["factorisations"] for n in results if n in reference)
    print(f"compared with the reference: {bad} differences beyond {relative:g}; factorisations {ft} against {fr}")
    return bad


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--keller", default=os.path.join(ROOT, "build", "bin", "keller"))
    ap.add_argument("--set", action="append", default=[], help="override for every run")
    ap.add_argument("--config", action="append", nargs="+", default=[], metavar=("NAME", "KEY=VALUE"),
                    help="a named configuration (overrides); several are alternated branch by branch")
    ap.add_argument("--only", nargs="+", default=None, help="branch names (e.g. owens_gamma)")
    ap.add_argument("--save", help="write the results (first configuration) as JSON")
    ap.add_argument("--compare", help="compare located and end values with a saved JSON table")
    ap.add_argument("--relative", type=float, default=1e-8)
    args = ap.parse_args()
    configs = [(c[0], c[1:]) for c in args.config] or [("as shipped", [])]
    names = [n for n in scenes() if args.only is None or n in args.only]
    print(f"machine: {machine()}")
    print(f"keller: {args.keller}; common overrides: {' '.join(args.set) or 'none'}")
    for label, ov in configs:
        print(f"configuration '{label}': {' '.join(ov) or 'no overrides'}")
    results = {label: {} for label, _ in configs}
    with tempfile.TemporaryDirectory() as work:
        for name in names:
            for label, ov in configs:
                r = trace(args.keller, name, args.set + ov, work)
                results[label][name] = r
                print(f"  {label}: {name}: {r['rows']} rows, {r['factorisations']} factorisations, "
                      f"{r['trace_seconds']:.2f} s", flush=True)
    totals = {label: print_table(f"configuration '{label}'", results[label]) for label, _ in configs}
    if len(configs) > 1:
        base = configs[0][0]
        for label, _ in configs[1:]:
            print(f"'{label}' / '{base}': factorisations {totals[label]['factorisations']}/"
                  f"{totals[base]['factorisations']}, trace time {totals[label]['trace_seconds']:.1f}/"
                  f"{totals[base]['trace_seconds']:.1f} s = {totals[label]['trace_seconds'] / totals[base]['trace_seconds']:.3f}")
    print(f"machine: {machine()}")
    first = results[configs[0][0]]
    if args.save:
        with open(args.save, "w") as f:
            json.dump(first, f, indent=1)
    status = 0
    if args.compare:
        with open(args.compare) as f:
            reference = json.load(f)
        for label, _ in configs:
            print(f"configuration '{label}':")
            status |= compare(results[label], reference, args.relative) > 0
    return status


if __name__ == "__main__":
    sys.exit(main())
