"""The Brusselator reaction-diffusion system written in Python:
    u_t = d1 u_xx + a - (b + 1) u + u^2 v,   v_t = d2 v_xx + b u - u^2 v   on (0, 1),
with no flux at both ends, by central differences on n intervals (the n + 1 nodes of u, then of v,
are the unknowns; the end rows use mirror nodes). Its homogeneous state u = a, v = b / a is a
solution for every b; its mode k oscillates from b = 1 + a^2 + (d1 + d2) (k pi)^2 on, so with no
Turing instability first (here d1 = d2: that needs b > (1 + a)^2) the first Hopf point is the
uniform mode's, at b = 1 + a^2 exactly.

    python3 examples/python/brusselator.py      # the homogeneous branch in b, with its Hopf point
"""

import sys

import numpy as np
import scipy.sparse as sp

import keller


class Brusselator(keller.Problem):
    name = "brusselator-python"
    parameters = {"b": 3.0, "a": 2.0}
    observable_names = ["u_mean", "v_mean"]

    def __init__(self, intervals=20, d1=0.01, d2=0.01):
        self.n, self.d1, self.d2 = intervals, d1, d2
        m = intervals + 1
        d = sp.diags([np.ones(m - 1), -2 * np.ones(m), np.ones(m - 1)], [-1, 0, 1], format="lil")
        d[0, 1] = d[m - 1, m - 2] = 2.0  # mirror nodes: no flux
        self.L = (float(intervals) ** 2 * d).tocsc()
        self.m = m

    def initial_guess(self, p):
        return np.concatenate([np.full(self.m, p["a"]), np.full(self.m, p["b"] / p["a"])])

    def residual(self, u, p):
        a, b, m = p["a"], p["b"], self.m
        x, y = u[:m], u[m:]
        fu = self.d1 * (self.L @ x) + a - (b + 1) * x + x * x * y
        fv = self.d2 * (self.L @ y) + b * x - x * x * y
        return -np.concatenate([fu, fv])  # B du/dt = -F

    def jacobian(self, u, p):
        b, m = p["b"], self.m
        x, y = u[:m], u[m:]
        return -sp.bmat([[self.d1 * self.L + sp.diags(-(b + 1) + 2 * x * y), sp.diags(x * x)],
                         [sp.diags(b - 2 * x * y), self.d2 * self.L + sp.diags(-x * x)]], format="csc")

    def mass_matrix(self, u, p):
        return sp.identity(2 * self.m, format="csc")

    def observables(self, u, p):
        return [u[:self.m].mean(), u[self.m:].mean()]


SCENE = {
    "continuation": {"parameter": "b", "upper": 6.0, "initial_step": 0.2, "max_step": 0.5,
                     "event_tolerance": 1e-10},
    "stability": {"enabled": True, "count": 4},
}

if __name__ == "__main__":
    branch = keller.trace(SCENE, sys.argv[1] if len(sys.argv) > 1 else "brusselator_python.h5", problem=Brusselator())
