#!/usr/bin/env python3
"""Benchmark of the study executors: one study of 16 M1 tasks (Oldroyd-B Wi branches of the
collapsible channel at 16 values of Gamma, to Wi = 0.1) run with --jobs 1 and --jobs 2 and under
mpirun with 2 and 3 ranks (1 and 2 workers), one after the other in this one run, from nothing
each time. Prints the machine, the wall time of each, the speed-up over --jobs 1, and the
scheduling overhead each executor measured (the gap between a task's end and the next task's
start on its worker, against a task's mean time).

    python3 runs/bench/bench_study.py [--keller build/bin/keller] [--tasks 16] [--mesh M1]
"""

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

from bench_support import machine

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--keller", default=os.path.join(ROOT, "build", "bin", "keller"))
    ap.add_argument("--tasks", type=int, default=16)
    ap.add_argument("--mesh", default="M1")
    ap.add_argument("--no-mpi", action="store_true")
    a = ap.parse_args()
    work = tempfile.mkdtemp(prefix="keller_bench_study_")
    gammas = [4.95e-5 * (6.6e-4 / 4.95e-5) ** (i / max(1, a.tasks - 1)) for i in range(a.tasks)]
    study = os.path.join(work, "bench.toml")
    with open(study, "w") as f:
        f.write(f'[study]\nscene = "{ROOT}/runs/scenes/collapsible_oldroyd_b_wi_low_gamma.toml"\n\n')
        f.write(f'[set]\n"output.xdmf" = false\n"mesh.name" = "{a.mesh}"\n"continuation.upper" = 0.1\n')
        f.write('"continuation.stops" = [0.05]\n\n[grid]\n"parameters.Gamma" = [' + ", ".join(f"{g:.6g}" for g in gammas))
        f.write(']\n\n[collect]\nevents = ["min_m1"]\nend = ["dP"]\n')
    runs = [("--jobs 1", [a.keller, "study", study, "--jobs", "1"]), ("--jobs 2", [a.keller, "study", study, "--jobs", "2"])]
    mpirun = shutil.which("mpirun")
    if mpirun and not a.no_mpi:
        flags = ["--allow-run-as-root", "--oversubscribe"] if os.geteuid() == 0 else ["--oversubscribe"]
        for n in (2, 3):
            runs.append((f"mpirun -n {n}", [mpirun, *flags, "-n", str(n), a.keller, "study", study]))
    print(f"machine: {machine()}")
    print(f"study: {a.tasks} tasks, Oldroyd-B Wi branches to Wi = 0.1 on {a.mesh}, Gamma from 4.95e-5 to 6.6e-4\n")
    print("| executor | wall s | speed-up | scheduling gap per task | of a task's time |")
    print("| --- | --- | --- | --- | --- |")
    base = None
    for name, cmd in runs:
        folder = os.path.join(work, re.sub(r"\W+", "_", name))
        t0 = time.perf_counter()
        p = subprocess.run(cmd + ["-o", folder], capture_output=True, text=True, cwd=work)
        wall = time.perf_counter() - t0
        if p.returncode != 0:
            sys.exit(f"{name} failed ({p.returncode}):\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
        m = re.search(r"scheduling: ([\d.]+) ms .* ([\d.]+)% of a task's mean ([\d.]+) s", p.stdout)
        base = base or wall
        gap = f"{m.group(1)} ms" if m else "-"
        share = f"{m.group(2)}% (task {m.group(3)} s)" if m else "-"
        print(f"| {name} | {wall:.1f} | {base / wall:.2f} | {gap} | {share} |", flush=True)
    shutil.rmtree(work)


if __name__ == "__main__":
    main()
