"""Periodic orbits as keller trace --orbit writes them, against keller evolve run to its limit cycle
(runs/dynamics/orbit_vs_evolve.py; docs/periodic_orbits.md): the 1D Brusselator's uniform orbits
past its Hopf point at b = 5 (a = 2)."""

import importlib.util
import os

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
