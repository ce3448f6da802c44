"""Periodic orbits as keller trace --orbit writes them, against keller evolve run to its limit cycle
(runs/dynamics/orbit_vs_evolve.py; docs/periodic_orbits.md): the 1D Brusselator's uniform orbits
past its Hopf point at b = 5 (a = 2)."""

import importlib.util
import os
import subprocess

import numpy as np
import scipy.sparse as sp

import keller

SOURCE = os.environ["KELLER_SOURCE"]
SCENES = os.path.join(SOURCE, "runs", "scenes")


def test_the_orbit_branch_agrees_with_evolve_at_its_limit_cycles(tmp_path):
    spec = importlib.util.spec_from_file_location("orbit_vs_evolve",
                                                  os.path.join(SOURCE, "runs", "dynamics", "orbit_vs_evolve.py"))
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    rows = script.main([os.path.join(SCENES, "brusselator1d_hopf.toml"), os.path.join(SCENES, "brusselator1d_evolve.toml"),
                        "--observable", "u_mean", "--section", "v_mean", "--stops", "5.15", "5.3",
                        "--set", "brusselator.intervals=4", "--work", str(tmp_path / "w"), "-o", str(tmp_path / "a.png")])
    assert [round(r[0], 12) for r in rows] == [5.15, 5.3]
    for b, T_orbit, T_evolve, A_orbit, A_evolve, mu2, decay in rows:
        # both at tolerances whose period errors are below 1e-7 (measured 4e-9 to 6e-8)
        assert abs(T_evolve / T_orbit - 1) < 1e-6, b
        # the amplitude from the samples' extremes refined by parabolas: 1e-5 at the orbit's 40 to 60
        # steps a period (measured 1.0e-5 and 3.8e-6)
        assert abs(A_evolve / A_orbit - 1) < 5e-5, b
        # the distance to the cycle shrinks by the nontrivial multiplier per period (measured to 1e-4
        # over 60 periods; 1% at 40, where the approach is not yet linear)
        assert abs(decay / mu2 - 1) < 0.01, b
    orbits = keller.open(str(tmp_path / "w" / "orbits.h5"))
    assert [p.kind for p in orbits.points("stop")] == ["stop", "stop"]
    assert os.path.getsize(tmp_path / "a.png") > 10000


def test_the_orbit_figure_classifies_stability_by_the_multipliers():
    from keller.plot.orbits import unstable
    mu = np.array([[1.0, 0.5, 0.1j],                # stable
                   [0.9, 1.0 + 1e-9, -1.2],          # the trivial one is the one nearest 1; -1.2 is outside
                   [1.1, 0.99, 0.2],                 # 0.99 is the trivial one: 1.1 makes it unstable
                   [0.6 + 0.9j, 0.6 - 0.9j, 1.0],   # a pair of modulus 1.08: unstable
                   [np.nan, np.nan, np.nan]])        # no multipliers: not called unstable
    assert unstable(mu).tolist() == [False, True, True, True, False]


def test_the_orbit_figure_draws_the_normal_forms_sqrt_law():
    from keller.plot.orbits import normal_form_prediction
    nf = {"amplitude:u": 0.3, "side": -1.0, "period": 3.0}
    amp, period = normal_form_prediction(nf, 2.0, "u", [1.0, 1.75, 2.0, 2.5])
    assert period == 3.0
    assert np.allclose(amp[:3], [0.6, 0.3, 0.0], rtol=0, atol=1e-15)  # 2 a sqrt(|d|) on the side -1
    assert np.isnan(amp[3])


def test_the_orbit_figure_of_a_traced_branch(tmp_path, keller_exe):
    scene = os.path.join(SCENES, "brusselator1d_hopf.toml")
    small = ["--set", "brusselator.intervals=4"]
    subprocess.run([keller_exe, "trace", scene, *small, "-o", str(tmp_path / "h.h5")], check=True, capture_output=True)
    subprocess.run([keller_exe, "trace", scene, *small, "--from", f"{tmp_path / 'h.h5'}:hopf1", "--orbit",
                    "--set", "stability.enabled=false", "--set", "continuation.upper=5.3", "-o",
                    str(tmp_path / "o.h5")], check=True, capture_output=True)
    from keller.plot.orbits import main, multipliers, unstable
    orbits = keller.open(str(tmp_path / "o.h5"))
    assert not unstable(multipliers(orbits.table)).any()  # the supercritical Hopf point's orbits are stable
    main([str(tmp_path / "o.h5"), "--y", "u_mean", "--hopf", f"{tmp_path / 'h.h5'}:hopf1",
          "-o", str(tmp_path / "o.png")])
    assert os.path.getsize(tmp_path / "o.png") > 10000


def test_an_orbit_branch_from_an_evolve_run_in_python(tmp_path):
    """keller.trace(orbit_from=RUN.h5): the branch through the last state of an evolve run on its
    limit cycle; at b = 5.5 the uniform orbit is the ODE's (T = 3.982851017, to 1e-6 as in
    OrbitCommand.StartsFromAnEvolveRunOnItsLimitCycle)."""
    common = {"brusselator.intervals": 4, "parameters.b": 5.5}
    run = str(tmp_path / "run.h5")
    keller.evolve(os.path.join(SCENES, "brusselator1d_evolve.toml"), run, verbose=False,
                  set={**common, "evolve.t_end": 100.0, "evolve.amplitude": 1e-2, "evolve.relative_tolerance": 1e-5,
                       "evolve.method": "sdirk4"})
    orbits = keller.trace(os.path.join(SCENES, "brusselator1d_hopf.toml"), str(tmp_path / "o.h5"), orbit_from=run,
                          verbose=False, set={**common, "stability.enabled": False, "continuation.upper": 5.6})
    assert abs(orbits["b"][0] - 5.5) < 1e-12
    assert abs(orbits["period"][0] / 3.982851017 - 1) < 1e-6


class AdaptiveControl(keller.Problem):
    """x' = y, y' = z, z' = -alpha z - y - x + x^2 (MatCont's adaptx, OrbitBranchTest.cpp) as
    B du/dt = -F with B = I: a Hopf point at alpha = 1 (omega = 1), and on its orbit branch a period
    doubling at alpha = 0.6303020062 with period 6.3640713394 (MatCont's manual: 0.6303020 and
    6.364071; the digits of an independent RK4 shooting code, docs/periodic_orbits.md). Three
    decoupled variables w_k' = -(k + 2) w_k, zero on every orbit, make it six unknowns: the steady
    states' eigenvalue solver (ARPACK) gives at most n - 2 eigenvalues, and the Hopf pair, -1 and
    -2 nearest zero need four; they add multipliers exp(-(k + 2) T) < 1e-5 and change nothing else."""
    name = "adaptive-control"
    parameters = {"alpha": 1.2}
    observable_names = ["x"]
    decay = np.array([2.0, 3.0, 4.0])

    def __init__(self):
        # J and B in the pattern's CSC structure (a 6 x 6 pattern, zeros kept): the fast path
        self.pattern = sp.csc_matrix(np.ones((6, 6)))
        self.J, self.B = self.pattern.copy(), self.pattern.copy()
        self.B.data[:] = np.eye(6).ravel(order="F")

    def initial_guess(self, p):
        return np.zeros(6)

    def residual(self, u, p):
        x, y, z = u[:3]
        return np.concatenate([[-y, -z, p["alpha"] * z + y + x - x * x], self.decay * u[3:]])

    def jacobian(self, u, p):
        J = np.zeros((6, 6))
        J[:3, :3] = [[0.0, -1.0, 0.0], [0.0, 0.0, -1.0], [1.0 - 2.0 * u[0], 1.0, p["alpha"]]]
        J[3:, 3:] = np.diag(self.decay)
        self.J.data[:] = J.ravel(order="F")
        return self.J

    def jacobian_pattern(self):
        return self.pattern

    def parameter_derivative(self, u, p, name):
        return np.array([0.0, 0.0, u[2], 0.0, 0.0, 0.0])

    def mass_matrix(self, u, p):
        return self.B

    def observables(self, u, p):
        return {"x": u[0]}


def test_switching_at_a_period_doubling_onto_the_doubled_branch(tmp_path):
    """keller trace --orbit --switch ORBITS.h5:pd1 (here keller.trace(orbit_switch=)): the adaptive
    control system's orbit branch from its Hopf point locates the period doubling at MatCont's value,
    and the doubled branch starts there with twice its period and lies on the side alpha < alpha_PD
    only (the single orbit run twice would continue to both sides). Its orbits are not the single
    one run twice: half their period from u0 they lie |Phi_(T/2)(u0) - u0| from u0, checked by an
    independent integration (scipy's DOP853 at rtol 1e-11), growing as sqrt(alpha_PD - alpha) (a
    pitchfork of the doubled map: the ratio 1.66 near the doubling to 1.60 at 0.57 in
    OrbitBranch.SwitchingOntoTheDoubledBranch)."""
    from scipy.integrate import solve_ivp
    accurate = {"orbit.method": "sdirk4", "orbit.relative_tolerance": 1e-7, "orbit.absolute_tolerance": 1e-10,
                "orbit.multipliers": 4, "stability.enabled": False}
    steady = keller.trace({"continuation": {"parameter": "alpha", "lower": 0.9, "upper": 1.3, "direction": "decrease",
                                            "initial_step": 0.05, "max_step": 0.1},
                           "stability": {"enabled": True, "count": 4}},
                          str(tmp_path / "steady.h5"), problem=AdaptiveControl(), verbose=False)
    assert abs(steady.point("hopf1").value - 1.0) < 1e-8
    orbit_scene = {"continuation": {"parameter": "alpha", "lower": 0.6, "upper": 1.3, "initial_step": 0.05,
                                    "max_step": 0.2},
                   "orbit": {"start_distance": 0.05}}
    orbits = keller.trace(orbit_scene, str(tmp_path / "orbits.h5"), orbit_from=(steady, "hopf1"), set=accurate,
                          problem=AdaptiveControl(), verbose=False)
    pd = orbits.point("pd1")
    # MatCont's 7 printed digits; the independent values to the grid's error at rtol 1e-7 (measured
    # 9e-9 and 1.2e-8; 2e-9 at rtol 1e-9 in OrbitBranch.AdaptiveControlPeriodDoublingsAgainstMatCont)
    assert abs(pd.value - 0.6303020) < 5e-8 and abs(pd["period"] - 6.364071) < 5e-7
    assert abs(pd.value - 0.6303020062) < 3e-8
    assert abs(pd["period"] - 6.3640713394) < 3e-8

    doubled = keller.trace(orbit_scene, str(tmp_path / "doubled.h5"), orbit_switch=(orbits, "pd1"),
                           set={**accurate, "continuation.lower": 0.57}, problem=AdaptiveControl(), verbose=False)
    alpha, period = np.asarray(doubled["alpha"]), np.asarray(doubled["period"])
    assert abs(alpha[0] - pd.value) < 1e-9
    assert abs(period[0] / (2.0 * pd["period"]) - 1.0) < 1e-8
    assert len(alpha) >= 4 and np.all(alpha[1:] < pd.value) and alpha[-1] <= 0.57 + 1e-9

    def rhs(t, u, a):
        x, y, z = u
        return [y, z, -a * z - y - x + x * x]

    ratios = []
    for s in doubled.solutions:
        if s.row == 0:
            continue
        a, T = float(doubled["alpha"][doubled.index_of_row(s.row)]), float(doubled["period"][doubled.index_of_row(s.row)])
        u0 = np.asarray(s.u)[:3]
        ends = [solve_ivp(rhs, (0.0, f * T), u0, args=(a,), method="DOP853", rtol=1e-11, atol=1e-13).y[:, -1]
                for f in (0.5, 1.0)]
        assert np.linalg.norm(ends[1] - u0) < 1e-6, a  # periodic with the doubled period
        gap = np.linalg.norm(ends[0] - u0)
        assert gap > 0.05, a
        ratios.append(gap / np.sqrt(pd.value - a))
    assert len(ratios) >= 3
    assert max(ratios) / min(ratios) < 1.06
