"""keller as an installed library: install the build into a prefix, move the prefix (the package
is relocatable), build examples/chafee_infante against it with only find_package(keller), and run
the user's program through keller's commands. Checks, with their tolerances:
  - the branch points of the trivial branch at the discrete eigenvalues (4 / h^2) sin^2(k h / 2),
    h = pi / 64, to 1e-8 (located to the scene's event tolerance 1e-10 in the residual);
  - the branch switched at the first is sin(x): u(pi/4) / max u = sin(pi/4) to 1e-3 at its first
    point (the amplitude's correction is O(a^2) of the mode, a = 0.1), lambda(a) = lambda_1 (1 +
    3 a^2 / 4 + O(a^4)) to 3% in its a^2 term, and stable (the smallest eigenvalue positive);
  - the Python package installed with it imports from the moved prefix, runs a trace in its
    process (the fold of bratu1d to 1e-9) and finds the installed keller program;
  - a study of the user's type completes its three tasks, with local workers and under mpirun
    (where it is installed): its tasks run in the user's program;
  - docs/own_problem.md's shell commands, extracted and run as written (HOME a scratch folder, so
    that $HOME/keller is the prefix; build, examples and runs linked to the source's), exit 0
    and make the tutorial's figures (the Chafee-Infante, Brusselator and Swift-Hohenberg ones);
  - --help-scene lists the user's keys; an unknown key, and a value the user's build refuses, exit 2
    with keller's message naming the file, line and key; --version is keller's.

Run by ctest (tests/CMakeLists.txt) as
    python3 tests/install/own_problem_test.py --build build --source . --scratch DIR"""

import csv
import math
import os
import shutil
import subprocess
import sys

from install_support import arguments, build_example, check, install_moved, run, table


def tutorial_commands(path):
    """The commands of the ```sh blocks of a markdown file, continuation lines joined."""
    commands, block = [], None
    with open(path) as f:
        for line in f:
            if line.startswith("```"):
                block = [] if line.strip() == "```sh" and block is None else None
                continue
            if block is not None:
                line = line.rstrip("\n")
                if commands and commands[-1].endswith("\\"):
                    commands[-1] = commands[-1][:-1] + " " + line.strip()
                elif line.strip() and not line.lstrip().startswith("#"):
                    commands.append(line.strip())
    return commands


def run_tutorial(build, source, scratch):
    """docs/own_problem.md's commands in a folder of their own, as a user runs them."""
    folder = os.path.join(scratch, "tutorial")
    os.makedirs(os.path.join(folder, "home"))
    os.symlink(build, os.path.join(folder, "build"))
    for d in ("examples", "runs"):
        os.symlink(os.path.join(source, d), os.path.join(folder, d))
    env = dict(os.environ, HOME=os.path.join(folder, "home"), PATH="/usr/bin:" + os.environ.get("PATH", ""))
    commands = tutorial_commands(os.path.join(source, "docs", "own_problem.md"))
    check(len(commands) >= 6, f"docs/own_problem.md has {len(commands)} commands")
    for c in commands:
        p = subprocess.run(["sh", "-c", c], cwd=folder, env=env, capture_output=True, text=True)
        if p.returncode != 0:
            sys.exit(f"FAIL: docs/own_problem.md: '{c}' exited {p.returncode}\n{p.stdout}\n{p.stderr}")
    figures = ["chafee_infante", "brusselator2d", "brusselator2d_pattern", "swift_hohenberg", "swift_hohenberg_patterns"]
    check(all(os.path.getsize(os.path.join(folder, f + ".png")) > 10000 for f in figures),
          f"docs/own_problem.md's {len(commands)} commands run and draw its {len(figures)} figures")


def check_python_package(prefix, source, scratch):
    """The Python package installed with keller (PREFIX/lib/python3.X/dist-packages/keller), moved
    with its prefix: it imports with that folder on the path, runs a trace in its process, and
    finds the installed keller program for a study's tasks."""
    import glob
    sites = glob.glob(os.path.join(prefix, "lib", "python3*", "dist-packages"))
    check(len(sites) == 1 and os.path.isdir(os.path.join(sites[0], "keller")), f"the Python package in {sites}")
    env = {k: v for k, v in os.environ.items() if k not in ("KELLER_EXE", "PYTHONPATH")}
    env["PYTHONPATH"] = sites[0]
    scene = os.path.join(source, "runs", "scenes", "bratu1d_fold.toml")
    code = ("import keller, keller.runs; print(keller.runs.keller_program()); "
            f"print(keller.trace({scene!r}, 'py.h5', verbose=False).point('fold1')['lambda'])")
    out = run(sys.executable, "-c", code, cwd=scratch, env=env).stdout.split()
    check(out[0] == os.path.join(prefix, "bin", "keller"), f"the installed package's keller program {out[0]}")
    check(abs(float(out[1]) - 3.5137191389) < 1e-9, f"a trace by the installed package: fold at {out[1]}")


def main():
    build, source, scratch = arguments()
    run_tutorial(build, source, scratch)
    prefix = install_moved(build, scratch)
    check_python_package(prefix, source, scratch)
    app = build_example(source, "chafee_infante", prefix, scratch)
    example = os.path.join(source, "examples", "chafee_infante")
    scene = os.path.join(example, "chafee_infante.toml")

    check(run(app, "--version").stdout == run(os.path.join(build, "bin", "keller"), "--version").stdout,
          "--version is keller's")
    keys = run(app, "solve", "--help-scene").stdout
    own = keys[keys.find("Keys of problem type 'chafee-infante'"):]
    check("[chafee_infante]  # the grid\n  intervals = 64\n" in own and "'collapsible-channel'" in keys,
          "--help-scene lists the user's keys and keller's problem types")

    run(app, "trace", scene, "-o", "trivial.h5", cwd=scratch)
    h = math.pi / 64
    bps = [r["lambda"] for r in table(app, "trivial.h5", scratch) if r["kind"] == "bp"]
    exact = [4 / h ** 2 * math.sin(k * h / 2) ** 2 for k in (1, 2, 3)]
    check(len(bps) == 3 and all(abs(b - e) < 1e-8 * e for b, e in zip(bps, exact)),
          f"branch points {bps} at the discrete eigenvalues {exact}")

    run(app, "trace", scene, "--switch", "trivial.h5:bp1", "-o", "mode1.h5", "--set", "continuation.upper=3",
        cwd=scratch)
    switched = table(app, "mode1.h5", scratch)
    first = switched[1]
    amplitude = first["u_max"]
    check(abs(first["u_quarter"] / amplitude - math.sin(math.pi / 4)) < 1e-3,
          f"the switched branch is sin(x): u(pi/4) / max u = {first['u_quarter'] / amplitude}")
    a2 = (first["lambda"] / exact[0] - 1) / amplitude ** 2
    check(abs(a2 / 0.75 - 1) < 0.03, f"lambda = lambda_1 (1 + c a^2) with c = {a2} (0.75 in the continuum)")
    check(all(r["sigma1_re"] > 0 for r in switched[1:]), "the switched branch is stable (supercritical)")

    # a study of the user's type, here and under mpirun: its tasks run in the user's program
    shutil.copy(scene, os.path.join(scratch, "chafee_infante.toml"))
    with open(os.path.join(scratch, "grid.toml"), "w") as f:
        f.write('[study]\nscene = "chafee_infante.toml"\ntask = "trace"\n[grid]\n'
                '"chafee_infante.intervals" = [16, 32, 64]\n')
    studies = [("grid", [app, "study", "grid.toml", "--jobs", "2"])]
    if shutil.which("mpirun"):
        studies.append(("grid_mpi", ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", "2", app, "study",
                                     "grid.toml", "-o", "grid_mpi"]))
    for folder, words in studies:
        run(*words, cwd=scratch)
        with open(os.path.join(scratch, folder, "grid.csv")) as f:
            tasks = list(csv.DictReader(f))
        check(len(tasks) == 3 and all(t["status"] == "done" for t in tasks), f"the study {' '.join(words[:3])}: "
              f"{len(tasks)} tasks done")

    with open(os.path.join(scratch, "bad_key.toml"), "w") as f:
        f.write('[problem]\ntype = "chafee-infante"\n[chafee_infante]\ninterval = 64\n')
    p = run(app, "solve", "bad_key.toml", cwd=scratch, expect=2)
    check("bad_key.toml:4" in p.stderr and "chafee_infante.interval" in p.stderr, "an unknown user key: " +
          p.stderr.strip().splitlines()[0])
    with open(os.path.join(scratch, "bad_value.toml"), "w") as f:
        f.write('[problem]\ntype = "chafee-infante"\n[chafee_infante]\nintervals = 66\n')
    p = run(app, "solve", "bad_value.toml", cwd=scratch, expect=2)
    check("chafee_infante.intervals" in p.stderr and "multiple of 4" in p.stderr, "a refused user value: " +
          p.stderr.strip().splitlines()[0])
    check(not os.path.exists(os.path.join(scratch, "bad_value.h5")), "nothing written for a refused scene")


if __name__ == "__main__":
    main()
