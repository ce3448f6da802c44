"""The 2D Allen-Cahn (real Ginzburg-Landau) equation written in Python:
    u_t = Laplace(u) + lambda (u - u^3) on the unit square, u = 0 on its boundary,
by the five-point stencil on an n x n grid (the (n - 1)^2 interior values are the unknowns). Its
trivial branch u = 0 has pitchfork branch points where lambda is an eigenvalue of the discrete
Laplacian, lambda_jk = 4 n^2 (sin^2(j pi / 2n) + sin^2(k pi / 2n)): simple for j = k, double for
j != k (the square's symmetry).

    python3 examples/python/allen_cahn2d.py     # the trivial branch, then the branch of its first branch point
"""

import math
import sys

import numpy as np
import scipy.sparse as sp

import keller


def laplacian(n):
    """-Laplace on the (n - 1)^2 interior nodes of an n x n grid of the unit square (CSC, sorted)."""
    m = n - 1
    d = sp.diags([-np.ones(m - 1), 2 * np.ones(m), -np.ones(m - 1)], [-1, 0, 1])
    eye = sp.identity(m)
    A = (float(n) ** 2 * (sp.kron(eye, d) + sp.kron(d, eye))).tocsc()
    A.sort_indices()
    return A


def diagonal_positions(A):
    """Where each diagonal entry of a CSC matrix with sorted indices is in its data."""
    return np.array([A.indptr[j] + np.searchsorted(A.indices[A.indptr[j]:A.indptr[j + 1]], j)
                     for j in range(A.shape[0])])


def branch_point(n, j, k):
    """lambda of the branch point of the mode sin(j pi x) sin(k pi y) on the n x n grid."""
    return 4 * n * n * (math.sin(j * math.pi / (2 * n)) ** 2 + math.sin(k * math.pi / (2 * n)) ** 2)


class AllenCahn2D(keller.Problem):
    name = "allen-cahn2d-python"
    parameters = {"lambda": 1.0}
    observable_names = ["u_max", "u_mean"]

    def __init__(self, n=16):
        self.n = n
        self.A = laplacian(n)
        self.diagonal = diagonal_positions(self.A)
        self.J = self.A.copy()

    def summary(self):
        return f"2D Allen-Cahn in Python, five-point stencil on a {self.n} x {self.n} grid, {(self.n - 1) ** 2} unknowns"

    def initial_guess(self, p):
        return np.zeros((self.n - 1) ** 2)

    def residual(self, u, p):
        return self.A @ u - p["lambda"] * (u - u ** 3)

    def jacobian(self, u, p):
        self.J.data[:] = self.A.data
        self.J.data[self.diagonal] -= p["lambda"] * (1 - 3 * u ** 2)
        return self.J

    def parameter_derivative(self, u, p, name):
        return -(u - u ** 3)

    def mass_matrix(self, u, p):
        return sp.identity(len(u), format="csc")

    def observables(self, u, p):
        return [np.abs(u).max(), u.mean()]


SCENE = {
    "parameters": {"lambda": 1.0},
    "continuation": {"parameter": "lambda", "upper": 60.0, "initial_step": 1.0, "max_step": 4.0,
                     "event_tolerance": 1e-10},
    "stability": {"enabled": True, "count": 6},
}

if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "allen_cahn2d"
    trivial = keller.trace(SCENE, out + "_trivial.h5", problem=AllenCahn2D())
    keller.trace(SCENE, out + "_mode11.h5", problem=AllenCahn2D(), switch=(trivial, "bp1"))
