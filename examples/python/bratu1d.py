"""The 1D Bratu problem written in Python: u'' + lambda e^u = 0 on (0, 1), u(0) = u(1) = 0, by
central differences on n intervals (the n - 1 interior values are the unknowns), the same
discretisation as keller's C++ problem bratu1d, so that both have the same fold (lambda_c =
3.51383 in the continuum limit).

    python3 examples/python/bratu1d.py            # traces it around its fold into bratu1d_python.h5
"""

import sys

import numpy as np
import scipy.sparse as sp

import keller


class Bratu1D(keller.Problem):
    name = "bratu1d-python"
    parameters = {"lambda": 0.0}
    parameter_docs = {"lambda": "Bratu parameter"}
    observable_names = ["u_mid", "u_max"]

    def __init__(self, intervals=128):
        self.n = intervals
        m, ih2 = intervals - 1, float(intervals) ** 2
        # -u'' as a CSC matrix whose structure is J's: the Jacobian only changes its diagonal
        self.A = sp.diags([-ih2 * np.ones(m - 1), 2 * ih2 * np.ones(m), -ih2 * np.ones(m - 1)], [-1, 0, 1],
                          format="csc")
        self.A.sort_indices()
        self.diagonal = np.array([self.A.indptr[j] + np.searchsorted(self.A.indices[self.A.indptr[j]:self.A.indptr[j + 1]], j)
                                  for j in range(m)])
        self.J = self.A.copy()

    def summary(self):
        return f"1D Bratu in Python, central differences on {self.n} intervals, {self.n - 1} unknowns"

    def initial_guess(self, p):
        return np.zeros(self.n - 1)

    def residual(self, u, p):
        return self.A @ u - p["lambda"] * np.exp(u)

    def jacobian(self, u, p):
        self.J.data[:] = self.A.data
        self.J.data[self.diagonal] -= p["lambda"] * np.exp(u)
        return self.J

    def parameter_derivative(self, u, p, name):
        return -np.exp(u)

    def mass_matrix(self, u, p):
        return sp.identity(self.n - 1, format="csc")

    def observables(self, u, p):
        n = self.n
        mid = u[n // 2 - 1] if n % 2 == 0 else 0.5 * (u[n // 2 - 1] + u[n // 2])
        return {"u_mid": mid, "u_max": u.max()}


SCENE = {
    "continuation": {"parameter": "lambda", "lower": 0.0, "stop_observable": "u_mid", "stop_above": 4.0,
                     "initial_step": 0.1, "max_step": 0.5, "event_tolerance": 1e-10},
}

if __name__ == "__main__":
    branch = keller.trace(SCENE, sys.argv[1] if len(sys.argv) > 1 else "bratu1d_python.h5", problem=Bratu1D())
    print("fold at lambda =", branch.point("fold1")["lambda"] if hasattr(branch, "point") else branch)
