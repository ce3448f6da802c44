"""Problems written in Python: F(u, p) = 0, continued by keller's C++ engine (docs/python.md).

A problem is a class with the residual and, for speed, its Jacobian as a scipy.sparse matrix:

    class Bratu1D(keller.Problem):
        name = "bratu1d-python"
        parameters = {"lambda": 0.0}               # name: initial value (a scene's [parameters] sets them)
        observable_names = ["u_max"]

        def initial_guess(self, p):   return np.zeros(n)
        def residual(self, u, p):     return A @ u - p["lambda"] * np.exp(u)
        def jacobian(self, u, p):     return A - scipy.sparse.diags(p["lambda"] * np.exp(u))
        def observables(self, u, p):  return {"u_max": u.max()}

and `keller.trace(scene, problem=Bratu1D())` traces it with everything a C++ problem has: events,
folds, branch points, switching, Hopf points, stability, two-parameter curves, time integration,
restarts. `p` is a dict of the parameters' present values; u a float64 array of the unknowns.

Required: `parameters`, `initial_guess(p)`, `residual(u, p)`. Optional, each with the default of
the C++ contract (core/Problem.hpp):

- `jacobian(u, p)`: dF/du, any scipy.sparse matrix (or a dense array). Default: one-sided finite
  differences, one residual per column (for small problems only).
- `jacobian_pattern()`: every entry of J (and B) that can be nonzero. Default: the entries of the
  Jacobian at the initial guess (explicit zeros included), or all entries without `jacobian`.
  A Jacobian with exactly the pattern's CSC structure is taken as it is (the fast path); another is
  scattered into it, and an entry outside it is a ValueError.
- `parameter_derivative(u, p, name)`: dF/dp. Default: central differences of the residual.
- `mass_matrix(u, p)`: B of B du/dt = -F (stability, time integration). Default: none, so a
  spectrum or `keller.evolve` is refused.
- `observable_names` and `observables(u, p)`: named scalars for the branch table (a dict by name,
  or a sequence in their order). Default: none.
- `monitor_names` and `monitors(u, p)`: named functions whose zeros are located events.
- `residual_scale`: the size of F for a solution of unit scale (Newton's tolerance is relative).
- `summary()`: one line on the discretisation; `name`: the problem's name; `parameter_docs`.

Raise `keller.NumericalFailure` where the state is outside the model's domain: Newton and the
step control react to it as to a C++ problem's failed Status. Any other exception stops the run
(keeping what it completed) and is raised again by the keller.* call.
"""

import numpy as np
import scipy.sparse as sp


class NumericalFailure(Exception):
    """Raised by a Python problem's method for a state outside its model's domain (the evaluation
    fails; the engine shortens its step or retries), not for a bug."""


class Problem:
    """The base of problems written in Python; see the module's doc for what to define."""

    name = "python"
    parameters = {}

    def initial_guess(self, p):
        raise NotImplementedError(f"{type(self).__name__} must define initial_guess(self, p)")

    def residual(self, u, p):
        raise NotImplementedError(f"{type(self).__name__} must define residual(self, u, p)")


def csc_parts(matrix, n, what):
    """(indptr, indices, data) of `matrix` (scipy.sparse or dense, n x n) in canonical CSC form
    (sorted indices, duplicates summed, explicit zeros kept), as int32 and float64 arrays."""
    if not sp.issparse(matrix):
        dense = np.asarray(matrix, dtype=float)
        if dense.shape != (n, n):
            raise ValueError(f"{what}() must return an {n} x {n} matrix, got shape {dense.shape}")
        matrix = sp.csc_matrix(dense)
    if matrix.shape != (n, n):
        raise ValueError(f"{what}() must return an {n} x {n} matrix, got shape {matrix.shape}")
    csc = matrix.tocsc() if matrix.format != "csc" else matrix
    if not csc.has_canonical_format:
        csc = csc.copy()
        csc.sum_duplicates()
    return (np.asarray(csc.indptr, dtype=np.int32), np.asarray(csc.indices, dtype=np.int32),
            np.asarray(csc.data, dtype=float))
