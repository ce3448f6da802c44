"""The cost of a problem written in Python against the same problem in C++, per continuation point,
in one run: the 2D Bratu problem with Q2 elements (examples/python/bratu2d.py, numpy and
scipy.sparse, against keller's bratu2d), traced around its fold to u_max = 3 by the same engine with
the same settings, at about 10^4 and 10^5 unknowns. The two discretisations are the same (their
folds agree to the location tolerance, printed); the Python problem's own time (residual, Jacobian,
dF/dp, observables, measured around its methods) says where the difference goes. Alternating
order, `--repeat` times, medians.

    PYTHONPATH=build/python python3 runs/bench/python_vs_cpp.py [--sides 50,158] [--repeat 3]"""

import argparse
import collections
import os
import statistics
import sys
import tempfile
import time

import keller

from bench_support import machine

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "examples", "python"))
from bratu2d import Bratu2D  # noqa: E402

CONTINUATION = {"parameter": "lambda", "lower": 0.0, "initial_step": 0.1, "max_step": 0.5, "event_tolerance": 1e-10,
                "stop_observable": "u_max", "stop_above": 3.0}


class Timed(Bratu2D):
    """Bratu2D with the time spent in each of its methods."""

    def __init__(self, n):
        super().__init__(n)
        self.seconds = collections.Counter()

    def _timed(self, name, method, *args):
        t = time.perf_counter()
        try:
            return method(*args)
        finally:
            self.seconds[name] += time.perf_counter() - t

    def residual(self, u, p):
        return self._timed("residual", super().residual, u, p)

    def jacobian(self, u, p):
        return self._timed("jacobian", super().jacobian, u, p)

    def parameter_derivative(self, u, p, name):
        return self._timed("dF/dp", super().parameter_derivative, u, p, name)

    def observables(self, u, p):
        return self._timed("observables", super().observables, u, p)


def run(n, python, folder):
    """(seconds per point, points, fold lambda, the problem's own seconds by method or None)."""
    out = os.path.join(folder, f"{'py' if python else 'cpp'}{n}.h5")
    for f in (out, out + ".part"):
        if os.path.exists(f):
            os.remove(f)
    problem = Timed(n) if python else None
    if python:
        branch = keller.trace({"continuation": CONTINUATION}, out, problem=problem, verbose=False)
    else:
        branch = keller.trace({"problem": {"type": "bratu2d"}, "bratu": {"intervals": n, "lambda": 0.0},
                               "continuation": CONTINUATION}, out, verbose=False)
    points = len(branch["lambda"])
    return branch["seconds"][-1] / points, points, branch.point("fold1")["lambda"], problem and problem.seconds


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sides", default="50,158", help="elements per side (unknowns (2n + 1)^2)")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    print(machine())
    with tempfile.TemporaryDirectory() as folder:
        for n in (int(s) for s in args.sides.split(",")):
            cpp, py, own = [], [], []
            for r in range(args.repeat):
                for python in ((False, True) if r % 2 == 0 else (True, False)):
                    per_point, points, fold, seconds = run(n, python, folder)
                    (py if python else cpp).append((per_point, points, fold))
                    if python:
                        own.append((seconds, per_point * points))
            c, p = statistics.median(x[0] for x in cpp), statistics.median(x[0] for x in py)
            print(f"\n{(2 * n + 1) ** 2} unknowns ({n}x{n} Q2), {cpp[0][1]} points (C++) and {py[0][1]} (Python); "
                  f"folds {cpp[0][2]:.10f} and {py[0][2]:.10f}")
            print(f"  per point: C++ {1e3 * c:.1f} ms, Python {1e3 * p:.1f} ms: ratio {p / c:.2f}")
            seconds, total = own[-1]
            inside = sum(seconds.values())
            print(f"  the Python problem's own time: {100 * inside / total:.0f}% of its run ("
                  + ", ".join(f"{k} {v:.2f} s" for k, v in seconds.most_common()) + f" of {total:.2f} s)")


if __name__ == "__main__":
    main()
