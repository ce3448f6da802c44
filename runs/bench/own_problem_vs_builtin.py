"""The cost of a Newton step of a user's finite-element problem (examples/brusselator2d, built
against the installed keller) against keller's built-in Bratu 2D of the same size, in one run:
each solved in turn by the user's program (it has keller's problem types too), its steps' times
read from the files (/solution/newton: assembly, factorisation, solve per iteration), medians.

Two "same sizes": the Brusselator's two fields on an n x n Q2 mesh against Bratu on the mesh with
the same number of unknowns (about sqrt 2 n per side), and on the 2n x 2n mesh, whose J has the
same number of nonzeros and whose LU the same work (nested dissection: (2 fields)^3 n^3 flops
against (2n)^3). The user's kernel and keller's assembler meet in assembly; the LU is the
problem's structure, not the user's code.

    python3 runs/bench/own_problem_vs_builtin.py --app EXAMPLE_BUILD/brusselator2d [--elements 16] [--repeat 5]"""

import argparse
import os
import re
import statistics
import subprocess
import tempfile

import h5py

from bench_support import machine


def solve(app, scene, folder):
    out = os.path.join(folder, "out.h5")
    p = subprocess.run([app, "solve", scene, "-o", out],
                       capture_output=True, text=True, cwd=folder, check=True)
    lu = re.search(r"n = (\d+), nnz\(A\) = (\d+), nnz\(L\+U\) = (\d+)", p.stdout)
    with h5py.File(out) as f:
        newton = f["/solution/newton"][()]
        cols = f["/solution/newton"].attrs["columns"]
    os.remove(out)
    cols = (cols.decode() if isinstance(cols, bytes) else cols).split(",")
    c = {name: i for i, name in enumerate(cols)}
    steps = [(row[c["assembly_seconds"]], row[c["factor_seconds"]], row[c["solve_seconds"]]) for row in newton
             if row[c["factor_seconds"]] > 0]
    return int(lu.group(1)), int(lu.group(2)), int(lu.group(3)), steps


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--app", required=True, help="the Brusselator example's program")
    ap.add_argument("--elements", type=int, default=16, help="Brusselator elements per side (even)")
    ap.add_argument("--repeat", type=int, default=5, help="solves of each problem, in turn")
    a = ap.parse_args()
    n = a.elements
    same_unknowns = round(((2 * (2 * n + 1) ** 2) ** 0.5 - 1) / 2)
    print("machine:", machine())
    with tempfile.TemporaryDirectory() as folder:
        scenes = {
            f"brusselator2d {n} x {n} (user)": f'[problem]\ntype = "brusselator2d"\n[brusselator2d]\nelements = {n}\n'
                                              "perturbation = 0.1\n[parameters]\nb = 2.5\n",
            f"bratu2d {same_unknowns} x {same_unknowns}, same unknowns": '[problem]\ntype = "bratu2d"\n[bratu]\n'
                                                                        f"intervals = {same_unknowns}\nlambda = 1.0\n",
            f"bratu2d {2 * n} x {2 * n}, same nnz(J)": f'[problem]\ntype = "bratu2d"\n[bratu]\nintervals = {2 * n}\n'
                                                     "lambda = 1.0\n",
        }
        paths = {}
        for i, (name, text) in enumerate(scenes.items()):
            paths[name] = os.path.join(folder, f"scene{i}.toml")
            with open(paths[name], "w") as f:
                f.write(text)
        sizes, steps = {}, {name: [] for name in scenes}
        for _ in range(a.repeat):
            for name in scenes:
                unknowns, nnz, nnz_lu, s = solve(a.app, paths[name], folder)
                sizes[name] = (unknowns, nnz, nnz_lu)
                steps[name] += s
    print(f"Newton step, medians over {a.repeat} solves of each in turn (seconds):")
    print(f"{'problem':<34} {'unknowns':>8} {'nnz(J)':>8} {'nnz(L+U)':>9} {'assembly':>9} {'factor':>9} "
          f"{'solve':>9} {'step':>9} {'user / it':>9}")
    user = None
    for name in scenes:
        med = [statistics.median(s[k] for s in steps[name]) for k in range(3)]
        step = statistics.median(sum(s) for s in steps[name])
        user = user or step
        u, nnz, nnz_lu = sizes[name]
        print(f"{name:<34} {u:>8} {nnz:>8} {nnz_lu:>9} {med[0]:>9.5f} {med[1]:>9.5f} {med[2]:>9.5f} {step:>9.5f} "
              f"{user / step:>9.2f}")
    print("machine after:", machine())


if __name__ == "__main__":
    main()
