"""keller's finite elements for a user's PDE: examples/brusselator2d and examples/swift_hohenberg
built against an installed and moved keller with only find_package(keller), and run through
keller's commands. Checks, with their tolerances:
  - each example's Jacobian and dF/dp against central differences (`solve --check-jacobian`, at
    its initial guess and near it): relative error below 1e-6, where an exact Jacobian gives about
    1e-9 and a wrong entry 1e-4 or more (tests/unit/JacobianCheckTest.cpp);
  - the Brusselator's Turing branch points (a = 2, Du = 1, Dv = 8, the square of side 10, 16 x 16
    Q2 elements) at b_k = (1 + Du k^2) (a^2 + Dv k^2) / (Dv k^2), k^2 the generalised eigenvalue
    of the Q2 stiffness and mass matrices of the mode (m, n) (the sum of two 1D P2 ones, computed
    here): (2, 2) and the double (3, 0)/(0, 3), to 1e-8 relative (located to the scene's event
    tolerance); the continuum's pi^2 (m^2 + n^2) / 100 differs by 3e-5 and 2e-4 relative;
  - traced with steps of 0.1, the five eigenvalues crossing within the step from 2.9 to 3.0 are
    located as three points, 0 -> 1, 1 -> 3, 3 -> 5 (two double eigenvalues), to 1e-8 relative:
    counts 0, 1 and 3 there (the crossing eigenvalues on the axis are not counted) and 5 at b = 3;
    with stability.count = 2 (crossings beyond the eigenvalues asked for) the same points and count;
  - the branch switched at the first is the pattern cos(pi x / 5) cos(pi y / 5): u at the middle of
    a wall against u at the corner, -1 at the bifurcation, within A at the first point (amplitude
    A = 0.015 after a first step of 0.005; the quadratic terms' harmonics add the same to both:
    0.8 A measured);
  - the Swift-Hohenberg branch points (Lx = 4 pi, Ly = 2.5 pi, 16 x 10 elements) at r = (1 - k^2)^2
    with k^2 as above, for the stripes (4, 0), the spots (2, 2), (4, 1) and (3, 2), to 1e-9
    absolute;
  - the stripes switched at the first: y-independent and odd about x = Lx / 8 (u_top = u_origin,
    u_quarter = -u_origin, to 1e-8 relative: symmetries of the equations that the branch keeps) and
    r - r_c = c A^2 with c within 3% of 3/4 (A = u_origin; the continuum's projection of cos^3);
  - the spots switched at the second: u_quarter = 0 (to 1e-8 of A) and c within 3% of 9/16.

Run by ctest (tests/CMakeLists.txt) as
    python3 tests/install/fe_examples_test.py --build build --source . --scratch DIR"""

import math
import os
import re

import numpy as np

from install_support import arguments, build_example, check, install_moved, run, table


def p2_eigenvalues(length, elements):
    """The generalised eigenvalues of the 1D P2 stiffness and mass matrices on a uniform mesh of
    (0, length) with natural ends, ascending: mode m of cos(m pi x / length)."""
    n, h = 2 * elements + 1, length / elements
    K, M = np.zeros((n, n)), np.zeros((n, n))
    Ke = np.array([[7, -8, 1], [-8, 16, -8], [1, -8, 7]]) / (3 * h)
    Me = np.array([[4, 2, -1], [2, 16, 2], [-1, 2, 4]]) * h / 30
    for e in range(elements):
        i = [2 * e, 2 * e + 1, 2 * e + 2]
        K[np.ix_(i, i)] += Ke
        M[np.ix_(i, i)] += Me
    L = np.linalg.inv(np.linalg.cholesky(M))
    return np.sort(np.linalg.eigvalsh(L @ K @ L.T))


def check_jacobian(app, scene, scratch):
    p = run(app, "solve", scene, "--check-jacobian", "-o", "checked.h5", cwd=scratch)
    errors = [float(e) for e in re.findall(r"relative error (\S+)", p.stdout)]
    check(len(errors) >= 4 and max(errors) < 1e-6 and "Jacobian check passed" in p.stdout,
          f"{os.path.basename(app)}: J v and dF/dp against central differences, errors {errors}")


def points(rows, kind):
    return [r for r in rows if r["kind"] == kind]


def brusselator(app, source, scratch):
    scene = os.path.join(source, "examples", "brusselator2d", "brusselator2d.toml")
    check_jacobian(app, scene, scratch)
    mu = p2_eigenvalues(10.0, 16)
    a, Du, Dv = 2.0, 1.0, 8.0

    def b(m, n):
        k2 = mu[m] + mu[n]
        return (1 + Du * k2) * (a * a + Dv * k2) / (Dv * k2)

    run(app, "trace", scene, "-o", "homogeneous.h5", cwd=scratch)
    rows = table(app, "homogeneous.h5", scratch)
    bps = [r["b"] for r in points(rows, "bp")]
    exact = [b(2, 2), b(3, 0)]
    check(len(bps) == 2 and all(abs(x - e) < 1e-8 * e for x, e in zip(bps, exact)),
          f"Brusselator branch points {bps} at the grid's b_k {exact}")

    run(app, "trace", scene, "-o", "coarse.h5", "--set", "continuation.initial_step=0.1", "--set",
        "continuation.max_step=0.1", "--set", "continuation.upper=3.0", cwd=scratch)
    rows = table(app, "coarse.h5", scratch)
    located = [(r["b"], r["unstable"]) for r in points(rows, "bp")]
    exact = [(b(2, 2), 0), (b(3, 0), 1), (b(3, 1), 3)]
    check(len(located) == 3 and all(abs(x - e) < 1e-8 * e and u == n for (x, u), (e, n) in zip(located, exact)),
          f"five crossings within one step of 0.1 located as three points (b, unstable there, the crossing "
          f"ones on the axis not counted): {located}")
    check(rows[-1]["unstable"] == 5 and abs(rows[-1]["b"] - 3.0) < 1e-12, "five unstable at b = 3")
    # with 2 eigenvalues asked for, the crossings beyond them are found all the same (the set grows)
    run(app, "trace", scene, "-o", "narrow.h5", "--set", "continuation.initial_step=0.1", "--set",
        "continuation.max_step=0.1", "--set", "continuation.upper=3.0", "--set", "stability.count=2", cwd=scratch)
    rows = table(app, "narrow.h5", scratch)
    bps = [r["b"] for r in points(rows, "bp")]
    check(len(bps) == 3 and all(abs(x - e) < 1e-8 * e for x, (e, _) in zip(bps, exact)) and rows[-1]["unstable"] == 5,
          f"stability.count = 2: the same three points {bps} and five unstable at b = 3")

    run(app, "trace", scene, "--switch", "homogeneous.h5:bp1", "-o", "pattern.h5", "--set",
        "continuation.initial_step=0.005", cwd=scratch)
    first = points(table(app, "pattern.h5", scratch), "point")[0]
    A, ratio = abs(first["u_corner"]), first["u_mid_wall"] / first["u_corner"]
    check(1e-3 < A < 0.1 and abs(ratio + 1) < A, f"the switched branch is cos(pi x / 5) cos(pi y / 5): u_mid_wall / "
          f"u_corner = {ratio} at amplitude {A} (-1 + O(A): the quadratic terms' harmonics)")


def swift_hohenberg(app, source, scratch):
    scene = os.path.join(source, "examples", "swift_hohenberg", "swift_hohenberg.toml")
    check_jacobian(app, scene, scratch)
    mx, my = p2_eigenvalues(4 * math.pi, 16), p2_eigenvalues(2.5 * math.pi, 10)

    def r(m, n):
        return (1 - mx[m] - my[n]) ** 2

    run(app, "trace", scene, "-o", "trivial.h5", cwd=scratch)
    bps = [p["r"] for p in points(table(app, "trivial.h5", scratch), "bp")]
    exact = [r(4, 0), r(2, 2), r(4, 1), r(3, 2)]
    check(len(bps) == 4 and all(abs(x - e) < 1e-9 for x, e in zip(bps, exact)),
          f"Swift-Hohenberg branch points {bps} at the grid's (1 - k^2)^2 {exact}")

    for bp, name, c_exact in (("bp1", "stripes", 0.75), ("bp2", "spots", 9 / 16)):
        run(app, "trace", scene, "--switch", "trivial.h5:" + bp, "-o", name + ".h5", "--set", "continuation.upper=0.1",
            cwd=scratch)
        first = points(table(app, name + ".h5", scratch), "point")[0]
        A = first["u_origin"]
        c = (first["r"] - exact[int(bp[2]) - 1]) / A ** 2
        check(abs(c / c_exact - 1) < 0.03, f"{name}: r - r_c = c A^2 with c = {c} ({c_exact} in the continuum), A = {A}")
        if name == "stripes":
            check(abs(first["u_top"] / A - 1) < 1e-8 and abs(first["u_quarter"] / A + 1) < 1e-8,
                  f"stripes: u_top / A = {first['u_top'] / A}, u_quarter / A = {first['u_quarter'] / A}")
        else:
            check(abs(first["u_quarter"] / A) < 1e-8 and abs(first["u_top"] / A - 1) < 1e-8,
                  f"spots: u_quarter / A = {first['u_quarter'] / A}, u_top / A = {first['u_top'] / A}")


def main():
    build, source, scratch = arguments()
    prefix = install_moved(build, scratch)
    brusselator(build_example(source, "brusselator2d", prefix, scratch), source, scratch)
    swift_hohenberg(build_example(source, "swift_hohenberg", prefix, scratch), source, scratch)


if __name__ == "__main__":
    main()
