"""Problems written in Python (keller.Problem; examples/python) continued by the C++ engine: folds,
branch points, Hopf points, switching, two-parameter curves and time integration against closed forms
and keller's own C++ problems."""

import os
import sys

import numpy as np
import pytest
import scipy.sparse as sp

import keller

SOURCE = os.environ["KELLER_SOURCE"]
sys.path.insert(0, os.path.join(SOURCE, "examples", "python"))

from allen_cahn2d import AllenCahn2D, branch_point  # noqa: E402
from bratu1d import Bratu1D  # noqa: E402
from brusselator import Brusselator  # noqa: E402

BRATU = os.path.join(SOURCE, "runs", "scenes", "bratu1d_fold.toml")
CONTINUATION = {"parameter": "lambda", "lower": 0.0, "stops": [1.0, 2.0, 3.0], "initial_step": 0.1, "max_step": 0.5,
                "event_tolerance": 1e-10, "stop_observable": "u_mid", "stop_above": 4.0}


def test_bratu1d_in_python_has_the_fold_of_the_cpp_problem(tmp_path):
    cpp = keller.trace(BRATU, tmp_path / "cpp.h5", verbose=False)
    py = keller.trace({"continuation": CONTINUATION}, tmp_path / "py.h5", problem=Bratu1D(128), verbose=False)
    # the same discretisation: folds located to event_tolerance 1e-10 agree to it
    assert abs(py.point("fold1")["lambda"] - cpp.point("fold1")["lambda"]) < 1e-10
    for k in (1, 2, 3):  # the requested values' states: the same solution
        assert abs(py.point(f"stop{k}")["u_mid"] - cpp.point(f"stop{k}")["u_mid"]) < 1e-10


def test_a_python_problem_without_its_jacobian_uses_finite_differences(tmp_path):
    class WithoutJacobian(Bratu1D):
        jacobian = None
        parameter_derivative = None

    del_attrs = WithoutJacobian
    del_attrs.jacobian = property(lambda self: (_ for _ in ()).throw(AttributeError))  # hasattr is False
    del_attrs.parameter_derivative = property(lambda self: (_ for _ in ()).throw(AttributeError))
    assert not hasattr(WithoutJacobian(16), "jacobian")
    exact = keller.trace({"continuation": CONTINUATION}, tmp_path / "a.h5", problem=Bratu1D(32), verbose=False)
    fd = keller.trace({"continuation": CONTINUATION}, tmp_path / "b.h5", problem=WithoutJacobian(32), verbose=False)
    # a one-sided difference Jacobian changes Newton's path, not the solutions: the fold to the
    # location tolerance times the Jacobian's relative error (about 1e-8)
    assert abs(fd.point("fold1")["lambda"] - exact.point("fold1")["lambda"]) < 1e-6


def test_allen_cahn2d_branch_points_at_the_grid_eigenvalues_and_its_pitchfork(tmp_path):
    n = 16
    scene = {"parameters": {"lambda": 1.0},
             "continuation": {"parameter": "lambda", "upper": 55.0, "initial_step": 1.0, "max_step": 4.0,
                              "event_tolerance": 1e-10},
             "stability": {"enabled": True, "count": 6}}
    trivial = keller.trace(scene, tmp_path / "trivial.h5", problem=AllenCahn2D(n), verbose=False)
    bps = trivial.points("bp")
    assert len(bps) == 2
    assert abs(bps[0]["lambda"] - branch_point(n, 1, 1)) < 1e-10 * branch_point(n, 1, 1)
    assert abs(bps[1]["lambda"] - branch_point(n, 1, 2)) < 1e-10 * branch_point(n, 1, 2)  # double: (1, 2), (2, 1)
    assert list(trivial["unstable"][[bps[0].index - 1, bps[0].index + 1]]) == [0, 1]
    # both sides of the pitchfork: u -> -u maps one onto the other
    scene["continuation"]["upper"] = 25.0
    up = keller.trace(scene, tmp_path / "up.h5", problem=AllenCahn2D(n), switch=(trivial, "bp1"), direction=1,
                      verbose=False)
    down = keller.trace(scene, tmp_path / "down.h5", problem=AllenCahn2D(n), switch=(trivial, "bp1"), direction=-1,
                        verbose=False)
    assert up.point("end")["lambda"] == pytest.approx(25.0, abs=1e-12)
    assert up.point("end")["u_mean"] == pytest.approx(-down.point("end")["u_mean"], rel=1e-8)
    assert abs(up.point("end")["u_mean"]) > 0.1


def test_brusselator_hopf_point_at_one_plus_a_squared_and_its_curve(tmp_path):
    scene = {"parameters": {"b": 3.0, "a": 2.0},
             "continuation": {"parameter": "b", "upper": 5.5, "initial_step": 0.2, "max_step": 0.5,
                              "event_tolerance": 1e-10},
             "stability": {"enabled": True, "count": 4}}
    branch = keller.trace(scene, tmp_path / "b.h5", problem=Brusselator(), verbose=False)
    hopf = branch.point("hopf1")
    assert abs(hopf["b"] - 5.0) < 1e-10  # 1 + a^2 (located to 5e-15)
    # the Hopf curve in (b, a): every point on b = 1 + a^2
    scene["continuation"].update({"lower": 1.0, "upper": 3.0, "max_step": 0.2})
    scene["stability"]["enabled"] = False  # a curve's points are not analysed
    curve = keller.trace(scene, tmp_path / "curve.h5", problem=Brusselator(), curve="hopf", curve_from=(branch, "hopf1"),
                         free="a", verbose=False)
    assert len(curve["a"]) >= 5 and curve["a"].max() == pytest.approx(3.0, abs=1e-12)
    np.testing.assert_allclose(curve["b"], 1 + curve["a"] ** 2, rtol=1e-8)


def test_time_integration_of_a_python_problem_grows_past_its_hopf_point(tmp_path):
    scene = {"parameters": {"b": 5.2, "a": 2.0},
             "evolve": {"t_end": 30.0, "perturbation": "computed", "amplitude": 1e-4, "shift_im": 2.0}}
    amplitudes = []
    series = keller.evolve(scene, tmp_path / "e.h5", problem=Brusselator(intervals=8),
                           callback=lambda p: amplitudes.append(p["u_mean"]), verbose=False)
    assert isinstance(series, keller.TimeSeries)
    # past the Hopf point the uniform mode grows at Re sigma = (b - 1 - a^2) / 2 = 0.1 per unit time
    early = np.ptp(amplitudes[: len(amplitudes) // 3])
    late = np.ptp(amplitudes[-len(amplitudes) // 3:])
    assert late > 5 * early


def test_python_exceptions_and_numerical_failures(tmp_path):
    class Broken(Bratu1D):
        def residual(self, u, p):
            if p["lambda"] > 2.0:
                raise KeyError("a bug in the residual")
            return super().residual(u, p)

    with pytest.raises(KeyError, match="a bug in the residual"):
        keller.trace({"continuation": CONTINUATION}, tmp_path / "x.h5", problem=Broken(32), verbose=False)
    kept = keller.open(str(tmp_path / "x.h5.part"))  # what it completed, to be continued
    assert len(kept["lambda"]) >= 4 and kept["lambda"].max() <= 2.0

    class Bounded(Bratu1D):
        def residual(self, u, p):
            if u.max() > 1.5:
                raise keller.NumericalFailure("u above 1.5 is outside this model")
            return super().residual(u, p)

    with pytest.raises(keller.KellerError) as e:
        keller.trace({"continuation": CONTINUATION}, tmp_path / "y.h5", problem=Bounded(32), verbose=False)
    assert e.value.code == 1  # the branch failed where the model ends; what it traced is kept
    assert "residual(): u above 1.5 is outside this model" in str(e.value)  # the failure's own words
    b = keller.open(str(tmp_path / "y.h5.part")) if os.path.exists(tmp_path / "y.h5.part") else keller.open(str(tmp_path / "y.h5"))
    assert b["u_max"].max() <= 1.5


def test_a_jacobian_entry_outside_the_pattern_is_a_value_error(tmp_path):
    class Outside(Bratu1D):
        def jacobian_pattern(self):
            return sp.identity(self.n - 1)

    with pytest.raises(ValueError, match="outside the Jacobian's pattern"):
        keller.trace({"continuation": CONTINUATION}, tmp_path / "z.h5", problem=Outside(16), verbose=False)


class Bratu1DWithMonitor(Bratu1D):
    """Bratu 1D with the monitor u_mid - 1: its zeros are located events."""

    monitor_names = ["u_mid_minus_1"]

    def monitors(self, u, p):
        return [self.observables(u, p)["u_mid"] - 1.0]


def test_a_python_problems_monitor_is_an_event_and_a_stored_point_restarts_it(tmp_path):
    branch = keller.trace({"continuation": CONTINUATION}, tmp_path / "m.h5", problem=Bratu1DWithMonitor(64),
                          verbose=False)
    events = branch.points("event")
    assert len(events) == 1  # u_mid grows along the branch, through 1 before the fold (u_mid = 1.19 there)
    assert abs(events[0]["u_mid"] - 1.0) < 1e-10
    assert events[0].monitor == "u_mid_minus_1"  # the monitor whose zero it is, read from the file
    assert branch.point("fold1").monitor is None
    assert events[0].row < branch.point("fold1").row
    # a restart from the event continues along the stored tangent, through the fold, to the same end
    restarted = keller.trace({"continuation": CONTINUATION}, tmp_path / "r.h5", problem=Bratu1DWithMonitor(64),
                             restart=(branch, "event1"), verbose=False)
    assert restarted["lambda"][0] == events[0]["lambda"]
    assert abs(restarted.point("fold1")["lambda"] - branch.point("fold1")["lambda"]) < 1e-10
    assert abs(restarted.point("end")["lambda"] - branch.point("end")["lambda"]) < 1e-10


def test_the_problem_of_docs_python_md_runs_as_written(tmp_path, monkeypatch):
    """The Bratu1D class of docs/python.md section 4, executed as written in a scratch folder: its
    branch has the C++ problem's fold (the same discretisation with 128 intervals)."""
    import re
    with open(os.path.join(SOURCE, "docs", "python.md")) as f:
        text = f.read()
    section = text[text.index("## 4. Problems written in Python"):]
    block = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    monkeypatch.chdir(tmp_path)
    scope = {}
    exec(compile(block.replace('"bratu.h5", problem', '"bratu.h5", verbose=False, problem'), "docs/python.md", "exec"),
         scope)
    cpp = keller.trace(BRATU, tmp_path / "cpp.h5", verbose=False)
    assert abs(scope["branch"].point("fold1")["lambda"] - cpp.point("fold1")["lambda"]) < 1e-9
