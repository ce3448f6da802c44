"""The 2D Bratu problem written in Python with finite elements: -Laplace(u) = lambda e^u on the
unit square, u = 0 on its boundary, biquadratic (Q2) elements on a uniform n x n mesh with 3 x 3
Gauss points: the discretisation of keller's C++ problem bratu2d (problems/analytic/Bratu2DProblem),
so that both have the same fold, written as a numpy user would: the stiffness matrix assembled once,
the nonlinear term evaluated for all elements at once and added into J's CSC data through a map
computed once (runs/bench/python_vs_cpp.py measures what it costs against the C++ problem).

    python3 examples/python/bratu2d.py 16       # around the fold into bratu2d_python.h5
"""

import sys

import numpy as np
import scipy.sparse as sp

import keller

# quadratic Lagrange shape functions at the nodes -1, 0, 1, and their derivatives, at s
_SHAPES = (lambda s: s * (s - 1) / 2, lambda s: 1 - s * s, lambda s: s * (s + 1) / 2)
_SLOPES = (lambda s: s - 0.5, lambda s: -2 * s, lambda s: s + 0.5)
_GAUSS = np.array([-np.sqrt(0.6), 0.0, np.sqrt(0.6)])
_WEIGHTS = np.array([5 / 9, 8 / 9, 5 / 9])


def q2_tables():
    """N[q, a] and dN/ds, dN/dt [q, a] at the 9 Gauss points q (s fastest), nodes a = i + 3 j
    (lexicographic), and the weights w[q]."""
    N, Ns, Nt, w = np.zeros((9, 9)), np.zeros((9, 9)), np.zeros((9, 9)), np.zeros(9)
    for qj in range(3):
        for qi in range(3):
            q = qi + 3 * qj
            s, t = _GAUSS[qi], _GAUSS[qj]
            w[q] = _WEIGHTS[qi] * _WEIGHTS[qj]
            for j in range(3):
                for i in range(3):
                    a = i + 3 * j
                    N[q, a] = _SHAPES[i](s) * _SHAPES[j](t)
                    Ns[q, a] = _SLOPES[i](s) * _SHAPES[j](t)
                    Nt[q, a] = _SHAPES[i](s) * _SLOPES[j](t)
    return N, Ns, Nt, w


class Bratu2D(keller.Problem):
    name = "bratu2d-python"
    parameters = {"lambda": 0.0}
    observable_names = ["u_max", "u_centre"]

    def __init__(self, n=16):
        self.n = n
        side = 2 * n + 1
        self.size = side * side
        # element connectivity: element (ei, ej) has the nodes (2 ei + i, 2 ej + j), a = i + 3 j
        ei, ej = np.meshgrid(np.arange(n), np.arange(n), indexing="xy")
        base = (2 * ej * side + 2 * ei).ravel()
        local = np.array([i + j * side for j in range(3) for i in range(3)])
        self.conn = base[:, None] + local[None, :]
        N, Ns, Nt, w = q2_tables()
        h = 1.0 / n
        detJ = h * h / 4
        self.N, self.wdet = N, w * detJ
        dNx, dNy = Ns * (2 / h), Nt * (2 / h)
        Ke = np.einsum("q,qa,qb->ab", self.wdet, dNx, dNx) + np.einsum("q,qa,qb->ab", self.wdet, dNy, dNy)
        rows = np.repeat(self.conn, 9, axis=1).ravel()
        cols = np.tile(self.conn, (1, 9)).ravel()
        K = sp.csc_matrix((np.tile(Ke.ravel(), n * n), (rows, cols)), shape=(self.size, self.size))
        K.sum_duplicates()
        K.sort_indices()
        # where each element entry (e, a, b) goes in the CSC data (keys column-major, increasing)
        keys = K.indices.astype(np.int64) + np.repeat(np.arange(self.size, dtype=np.int64), np.diff(K.indptr)) * self.size
        self.slot = np.searchsorted(keys, cols.astype(np.int64) * self.size + rows)
        # the boundary: its rows are u = 0
        x = np.arange(side)
        on_edge = (x == 0) | (x == side - 1)
        self.boundary = np.flatnonzero((on_edge[None, :] | on_edge[:, None]).ravel())
        self.boundary_entries = np.isin(K.indices, self.boundary)
        diagonal = np.array([K.indptr[j] + np.searchsorted(K.indices[K.indptr[j]:K.indptr[j + 1]], j)
                             for j in self.boundary])
        self.K = K
        self.Kdata = K.data.copy()
        self.Kdata[self.boundary_entries] = 0.0
        self.Kdata[diagonal] = 1.0  # the boundary rows of K u are u
        self.K_bc = sp.csc_matrix((self.Kdata, K.indices, K.indptr), shape=K.shape)
        self.J = self.K_bc.copy()
        self.centre = n * side + n

    def summary(self):
        return f"2D Bratu in Python, Q2 elements on a uniform {self.n}x{self.n} mesh, {self.size} unknowns"

    def initial_guess(self, p):
        return np.zeros(self.size)

    def _source(self, u):
        """exp(u) at the Gauss points of every element (elements x 9)."""
        return np.exp(u[self.conn] @ self.N.T)

    def residual(self, u, p):
        source = (self._source(u) * self.wdet) @ self.N  # int phi_a e^u, elements x 9
        F = self.K_bc @ u - p["lambda"] * np.bincount(self.conn.ravel(), source.ravel(), minlength=self.size)
        F[self.boundary] = u[self.boundary]
        return F

    def jacobian(self, u, p):
        weighted = self._source(u) * self.wdet
        Je = np.einsum("eq,qa,qb->eab", weighted, self.N, self.N)
        self.J.data[:] = self.Kdata - p["lambda"] * np.bincount(self.slot, Je.ravel(), minlength=len(self.Kdata))
        self.J.data[self.boundary_entries] = self.Kdata[self.boundary_entries]
        return self.J

    def parameter_derivative(self, u, p, name):
        source = (self._source(u) * self.wdet) @ self.N
        dF = -np.bincount(self.conn.ravel(), source.ravel(), minlength=self.size)
        dF[self.boundary] = 0.0
        return dF

    def observables(self, u, p):
        return [u.max(), u[self.centre]]


if __name__ == "__main__":
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 16
    scene = {"continuation": {"parameter": "lambda", "lower": 0.0, "initial_step": 0.1, "max_step": 0.5,
                              "event_tolerance": 1e-10, "stop_observable": "u_max", "stop_above": 3.0}}
    branch = keller.trace(scene, "bratu2d_python.h5", problem=Bratu2D(n))
