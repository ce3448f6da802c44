#!/usr/bin/env python3
"""Every figure of the reference study (Chakraborty and Prakash's collapsible channel with a
finite-thickness wall) by one command, from branch files keller makes itself:

    PYTHONPATH=build/python python3 runs/paper/make_all.py [--jobs 2] [--keller build/bin/keller] [--only fig05 fig13]

1. runs the studies of runs/paper (steady_shear, gamma, thickness, wi, wi_m3, wi_thickness; with
   --only, those the figures read) with
   `keller study STUDY.toml --jobs N -o DATA/STUDY`: a task already computed for its current
   scene (the study's hash) is skipped, an interrupted one continued;
2. draws figures 1-16 into runs/paper/figures/ (figNN_name.png), N at a time, and writes there
   costs.md: what the branches each figure reads cost keller (points, seconds).

The data folder (runs/paper/data by default) holds the studies' branch files and tables; delete
it to start from nothing. A figure whose data is missing (a failed task) is reported and the
others are drawn; the exit code is then 1. docs/paper.md says what each figure shows, its mesh
and its cost."""

import argparse
import multiprocessing
import os
import subprocess
import sys
import time
import tomllib
import traceback

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))

STUDIES = ["steady_shear", "gamma", "thickness", "wi", "wi_m3", "wi_thickness"]


def run_studies(keller, data, jobs, names):
    """Runs each study (skipping what is done); returns {study: (exit code, seconds)}."""
    out = {}
    for name in names:
        cmd = [keller, "study", os.path.join(HERE, name + ".toml"), "--jobs", str(jobs), "-o", os.path.join(data, name)]
        print(f"make_all: {' '.join(cmd)}", flush=True)
        t0 = time.monotonic()
        code = subprocess.call(cmd)
        out[name] = (code, time.monotonic() - t0)
        print(f"make_all: study {name}: exit {code}, {out[name][1]:.1f} s", flush=True)
    return out


def draw(job):
    """Draws one figure in a worker process; returns (name, path or error text, seconds)."""
    name, data, figures_dir = job
    import figures
    import paper_context
    import paper_data
    import paper_style

    paper_style.setup()
    t0 = time.monotonic()
    ctx = paper_context.Context(data, figures_dir)
    try:
        path = getattr(figures, name)(ctx)
        return name, path, time.monotonic() - t0, True, sorted(set(ctx.inputs))
    except paper_data.MissingData as e:
        return name, f"not drawn: {e}", time.monotonic() - t0, False, []
    except Exception:  # a fault in one figure's code: its traceback, and the others are still drawn
        return name, "failed:\n" + traceback.format_exc(), time.monotonic() - t0, False, []


def task_record(branch):
    """The study's record of the task that wrote a branch file (STUDY/tasks/NAME.toml)."""
    with open(os.path.splitext(branch)[0] + ".toml", "rb") as f:
        return tomllib.load(f)


def costs(drawn, path):
    """A Markdown table of what each figure's branches cost keller (the continuation's seconds and
    the tasks' processes, summed over the branch files it read), written through PATH.part."""
    lines = ["| figure | branches | unknowns | points | continuation s | process s |", "| --- | --- | --- | --- | --- | --- |"]
    for name, _, _, ok, inputs in drawn:
        if not ok:
            continue
        recs = [task_record(b) for b in inputs]
        sizes = sorted({int(r["unknowns"]) for r in recs})
        lines.append(f"| {name} | {len(recs)} | {sizes[0]}-{sizes[-1]} | {sum(int(r['points']) for r in recs)} | "
                     f"{sum(float(r['seconds']) for r in recs):.0f} | {sum(float(r['process_seconds']) for r in recs):.0f} |")
    text = "\n".join(lines) + "\n"
    with open(path + ".part", "w") as f:
        f.write(text)
    os.replace(path + ".part", path)
    return text


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="study workers and figure processes")
    ap.add_argument("--keller", default=os.path.join(ROOT, "build", "bin", "keller"), help="the keller program")
    ap.add_argument("--data", default=os.path.join(HERE, "data"), help="folder of the studies' output")
    ap.add_argument("--figures", default=os.path.join(HERE, "figures"), help="folder of the figures")
    ap.add_argument("--only", nargs="+", metavar="FIG",
                    help="draw only these figures (fig01 ... fig16), running only the studies they read")
    ap.add_argument("--no-studies", action="store_true", help="draw from the data as it is, run no study")
    a = ap.parse_args()
    import figures

    names = [f.__name__ for f in figures.ALL]
    if a.only:
        unknown = [n for n in a.only if n not in names]
        if unknown:
            sys.exit(f"make_all: no figure {', '.join(unknown)} (figures: {', '.join(names)})")
        names = a.only
    if a.jobs < 1:
        sys.exit("make_all: --jobs must be at least 1")
    if not a.no_studies and not os.access(a.keller, os.X_OK):
        sys.exit(f"make_all: no keller program at {a.keller} (build it, or give --keller)")
    for folder in (a.data, a.figures):
        os.makedirs(folder, exist_ok=True)

    t0 = time.monotonic()
    needed = {st for n in names for st in figures.STUDIES[n]}
    studies = {} if a.no_studies else run_studies(a.keller, a.data, a.jobs, [st for st in STUDIES if st in needed])
    t_studies = time.monotonic() - t0
    with multiprocessing.Pool(min(a.jobs, len(names))) as pool:
        drawn = pool.map(draw, [(n, a.data, a.figures) for n in names])
    t_all = time.monotonic() - t0

    for name, what, seconds, _, _ in drawn:
        print(f"  {name}: {what} ({seconds:.1f} s)")
    if not a.only:
        print("what each figure's branches cost (also in " + os.path.join(a.figures, "costs.md") + "):")
        print(costs(drawn, os.path.join(a.figures, "costs.md")), end="")
    failed = [n for n, _, _, ok, _ in drawn if not ok] + [s for s, (code, _) in studies.items() if code != 0]
    print(f"make_all: studies {t_studies:.1f} s, figures {t_all - t_studies:.1f} s, total {t_all:.1f} s"
          + (f"; not done: {', '.join(failed)}" if failed else ""))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
