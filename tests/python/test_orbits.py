"""Periodic orbits as keller trace --orbit writes them, against keller evolve run to its limit cycle
(runs/dynamics/orbit_vs_evolve.py; docs/periodic_orbits.md): the 1D Brusselator's uniform orbits
past its Hopf point at b = 5 (a = 2)."""

import importlib.util
import os
import subprocess

import numpy as np

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
