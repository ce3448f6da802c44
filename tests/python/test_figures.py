"""The figures of the package (python3 -m keller.plot KIND, keller.convergence,
keller.mesh_convergence) on files keller writes: each kind draws its figure from the files alone;
the labels name only the scene keys that tell files apart; a figure never replaces an input; bad
input is refused without a figure; and the policies that make them ready to publish, as functions
on synthetic inputs with numbers (keller.plot.curves, keller.labels, keller.convergence), with
every figure module run in-process with warnings turned into errors."""

import contextlib
import csv
import importlib
import io
import os
import subprocess
import sys
import warnings

import numpy as np
import pytest

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from keller.convergence import settled_order  # noqa: E402
from keller.labels import QUANTITIES, distinguishing_labels, quantity  # noqa: E402
from keller.plot.curves import (boxes_overlap, branch_splines, parameter_slopes, place_labels,  # noqa: E402
                                segment_states, smooth_branch)


def figure(*words, cwd, module="keller.plot"):
    """Runs a figure command with this Python (the package on its path as the test's)."""
    return subprocess.run([sys.executable, "-m", module, *map(str, words)], cwd=cwd, capture_output=True, text=True,
                          env=dict(os.environ, MPLBACKEND="Agg"))


def drawn(path, at_least=10000):
    """A complete figure: its file exists with no temporary name beside it."""
    return os.path.getsize(path) > at_least and not os.path.exists(str(path) + ".part")


@pytest.fixture(scope="module")
def shear_files(run):
    """Three steady-shear branches of different laws (every scene lists every law constant)."""
    files = []
    for name, sets in (("g", ['fluid.model="giesekus"', "parameters.alpha=0.3"]), ("p", []),
                       ("o", ['fluid.model="oldroyd-b"'])):
        words = ["trace", run.scene("steady_shear_ptt.toml"), "-o", f"shear_{name}.h5", "--set", "output.xdmf=false"]
        for s in sets:
            words += ["--set", s]
        run(*words)
        files.append(run.path(f"shear_{name}.h5"))
    return files


def test_labels_name_only_the_constants_a_law_has(shear_files):
    assert distinguishing_labels(shear_files) == ["model = giesekus, alpha = 0.3",
                                                  "model = ptt-linear, epsilon = 0.25, xi = 0.0", "model = oldroyd-b"]
    assert distinguishing_labels(shear_files[:1]) == ["shear_g.h5"]
    # a multi-mode fluid's mode times are labelled by their mode, other names by themselves
    assert quantity("time_fast") == r"$\lambda_k / \lambda$ of mode fast"
    assert quantity("time_") == "time_" and quantity("Wi") == "Wi"


def test_rheometry_with_measured_points(shear_files, tmp_path):
    (tmp_path / "m.csv").write_text("rate,eta_p\n1,0.99\n100,0.5\n")
    (tmp_path / "bad.csv").write_text("rate,eta_p\n1,x\n")
    ok = figure("rheometry", *shear_files, "--rate", "--data", "m.csv", "-o", "r.png", cwd=tmp_path)
    assert ok.returncode == 0, ok.stderr
    assert drawn(tmp_path / "r.png")
    bad = figure("rheometry", *shear_files, "--rate", "--data", "bad.csv", "-o", "b.png", cwd=tmp_path)
    assert bad.returncode == 2 and "bad.csv" in bad.stderr
    assert not os.path.exists(tmp_path / "b.png")


def test_branch_diagrams(bratu_branch, pitchfork_branch, fold_curve, tmp_path):
    for words, out in (([bratu_branch, "--y", "u_mid"], "b.png"), ([pitchfork_branch, "--y", "u_quarter"], "p.png"),
                       ([fold_curve, "--y", "lambda"], "c.png")):
        p = figure("branch", *words, "-o", out, cwd=tmp_path)
        assert p.returncode == 0, p.stderr
        assert p.stdout.strip() == f"wrote {out}" and drawn(tmp_path / out)
    p = figure("branch", bratu_branch, "--y", "no_such", "-o", "x.png", cwd=tmp_path)
    assert p.returncode == 1 and "no observable 'no_such'" in p.stderr and not os.path.exists(tmp_path / "x.png")


def test_a_figure_never_replaces_its_input(bratu_branch, tmp_path):
    before = open(bratu_branch, "rb").read()
    p = figure("branch", bratu_branch, "--y", "u_mid", "-o", bratu_branch, cwd=tmp_path)
    assert p.returncode != 0 and "same file as the input" in p.stderr
    os.symlink(bratu_branch, tmp_path / "link.png")
    p = figure("branch", bratu_branch, "--y", "u_mid", "-o", "link.png", cwd=tmp_path)
    assert p.returncode != 0 and "not a regular file" in p.stderr
    assert open(bratu_branch, "rb").read() == before


def test_the_collapsible_channels_figures(channel_branch, tmp_path):
    p = figure("collapsible", channel_branch, "-o", "c", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    for f in ("branch", "interface", "path", "wall", "fields"):
        assert drawn(tmp_path / f"c_{f}.png"), f
    p = figure("interfaces", "--newtonian", channel_branch, channel_branch, "-o", "i.png", cwd=tmp_path)
    assert p.returncode == 0 and drawn(tmp_path / "i.png"), p.stderr
    p = figure("field", channel_branch, "--field", "velocity:vx", "-o", "f.png", cwd=tmp_path)
    assert p.returncode == 0 and drawn(tmp_path / "f.png"), p.stderr
    p = figure("field", channel_branch, "--field", "velocity:vz", "-o", "g.png", cwd=tmp_path)
    assert p.returncode == 1 and "has the components vx, vy, not 'vz'" in p.stderr
    p = figure("flow", channel_branch, "-o", "flow.png", cwd=tmp_path)
    assert p.returncode == 0 and drawn(tmp_path / "flow.png"), p.stderr
    assert p.stdout.startswith("psi: q = ")


def test_a_time_series_and_a_study(time_series, study_folder, tmp_path):
    p = figure("evolve", time_series, "--log", "-o", "e.png", cwd=tmp_path)
    assert p.returncode == 0 and drawn(tmp_path / "e.png"), p.stderr
    p = figure("study", study_folder, "--x", "bratu.intervals", "--y", "event:fold", "-o", "s.png", cwd=tmp_path)
    assert p.returncode == 0 and drawn(tmp_path / "s.png"), p.stderr
    p = figure(os.path.join(study_folder, "s.h5"), "--mesh", "bratu.intervals", "--resolution", "bratu.intervals",
               "--observables", "event:fold", "--csv", "conv.csv", cwd=tmp_path, module="keller.convergence")
    assert p.returncode == 0, p.stderr
    with open(tmp_path / "conv.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert [r["mesh"] for r in rows] == ["16", "32"]


def test_mesh_convergence_of_a_branch(run, tmp_path):
    files = []
    for n in (16, 32, 64):
        run("trace", run.scene("bratu1d_fold.toml"), "-o", f"mc{n}.h5", "--set", f"bratu.intervals={n}",
            "--set", "output.xdmf=false")
        files.append(run.path(f"mc{n}.h5"))
    p = figure(*files, "--labels", "h16", "h32", "h64", "--observables", "u_mid", "--csv", "c.csv", cwd=tmp_path,
               module="keller.mesh_convergence")
    assert p.returncode == 0, p.stderr
    assert "mesh converged (h32 -> h64 within 0.01 in u_mid) up to lambda = 2" in p.stdout
    with open(tmp_path / "c.csv", newline="") as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["lambda", "u_mid:h16->h32", "u_mid:h32->h64"]
    # second order: halving h divides the change by 4
    for r in rows[1:]:
        assert float(r[1]) / float(r[2]) == pytest.approx(4.0, abs=0.1)


def test_the_dispatcher(tmp_path):
    p = figure("no_such_kind", cwd=tmp_path)
    assert p.returncode == 2 and "no figure kind 'no_such_kind'" in p.stderr
    p = figure("--help", cwd=tmp_path)
    assert p.returncode == 0 and "collapsible" in p.stdout
    p = figure("branch", "--help", cwd=tmp_path)
    assert p.returncode == 0 and p.stdout.startswith("usage: python3 -m keller.plot branch")


# --- the policies of the figures ---------------------------------------------------------


def fold_rows():
    """A fold in the parameter, x(s) = 2 s - s^2 (largest, 1, at s = 1), sampled at rows that miss
    s = 1, with the stored slopes dx/ds = 2 - 2 s; rows out of order and one written twice, as a
    branch file has them where a point was located by bisection."""
    s = np.array([0.0, 0.35, 1.6, 0.8, 1.25, 2.0, 0.8])
    return s, 2 * s - s ** 2, np.sin(s), 2 - 2 * s


def test_the_smooth_curve_passes_through_every_point_with_the_stored_slope():
    s, x, y, slope = fold_rows()
    fx, fy, rows = branch_splines(s, x, y, slope)
    assert list(s[rows]) == sorted(set(s))  # sorted by s, the repeated row dropped
    assert np.abs(fx(s[rows]) - x[rows]).max() <= 1e-12 and np.abs(fy(s[rows]) - y[rows]).max() <= 1e-12
    assert np.abs(fx.derivative()(s[rows]) - slope[rows]).max() <= 1e-12
    ss, xs, ys, seg, kept = smooth_branch(s, x, y, slope)
    on_rows = np.isin(ss, s)
    assert on_rows.sum() == len(rows) and np.array_equal(xs[on_rows], x[rows])  # every row exactly


def test_a_fold_is_drawn_smoothly_not_at_a_polygon_corner():
    s, x, y, slope = fold_rows()
    _, xs, _, _, _ = smooth_branch(s, x, y, slope)
    assert abs(xs.max() - 1.0) < 1e-3  # the fold's value: the Hermite spline of a parabola is exact
    assert 1.0 - x.max() > 0.03  # the polygon's corner is far from it
    # with the fold located as a row (as keller writes it), the curve turns at the row itself
    s2, x2, y2, d2 = (np.append(a, b) for a, b in zip(fold_rows(), (1.0, 1.0, np.sin(1.0), 0.0)))
    _, xs2, _, _, _ = smooth_branch(s2, x2, y2, d2)
    assert abs(xs2.max() - 1.0) <= 1e-12


def test_a_stored_slope_that_disagrees_with_both_secants_falls_back_to_pchip():
    s, x = np.array([0.0, 1.0, 2.0, 3.0]), np.array([0.0, 1.0, 2.0, 3.0])
    d = parameter_slopes(s, x, np.array([1.0, -1.0, np.nan, 1.0]))
    assert d[0] == 1.0 and d[3] == 1.0 and d[1] == pytest.approx(1.0) and d[2] == pytest.approx(1.0)
    # at a fold the secants differ in sign: a stored slope agrees with one of them and is kept
    s, x = np.array([0.0, 1.0, 2.0]), np.array([0.0, 1.0, 0.0])
    assert parameter_slopes(s, x, np.array([2.0, 0.1, -2.0]))[1] == 0.1


def test_stable_unstable_and_not_analysed_segments():
    assert list(segment_states([0, 0, 1, 1, np.nan, 0])) == ["stable", "unstable", "unstable", "unstable",
                                                             "not analysed"]


def test_labels_of_clustered_points_do_not_overlap():
    fig, ax = plt.subplots(figsize=(5, 4))
    rng = np.random.default_rng(3)
    points = [(1.0 + 0.02 * rng.standard_normal(), 1.0 + 0.02 * rng.standard_normal()) for _ in range(8)]
    points += [(0.2, 0.2), (1.8, 1.8)]
    ax.plot(*zip(*points), "o")
    ax.set_xlim(0, 2)
    ax.set_ylim(0, 2)
    fig.tight_layout()
    labels = place_labels(ax, points, [f"fold{k + 1}" for k in range(len(points))])
    assert len(labels) == len(points) and not boxes_overlap(labels)
    plt.close(fig)


def test_the_convergence_warning():
    h = 1.0 / np.array([8, 16, 32, 64, 128])
    assert settled_order(h, 1.0 + 3 * h ** 2, 2.0) == (True, pytest.approx([2.0, 2.0, 2.0]), "")
    # differences shrinking as 2^-1.2, 2^-1.9, 2^-2.0 with h halved: orders 1.2, 1.9, 2.0
    d = np.cumprod([1.0, 2 ** -1.2, 2 ** -1.9, 2 ** -2.0])
    q = np.concatenate(([0.0], np.cumsum(d)))
    settled, orders, why = settled_order(h, q, 2.0)
    assert not settled and orders == pytest.approx([1.2, 1.9, 2.0]) and "differ by more than 0.25" in why
    assert not settled_order(h[:2], q[:2], 2.0)[0]  # two meshes: no order
    assert settled_order(h[:3], 1.0 + h[:3] ** 2, 2.0)[0]  # three: the one order is the formal one
    assert not settled_order(h[:3], 1.0 + h[:3], 2.0)[0]


def test_names_on_axes():
    assert quantity("parameters.Gamma") == quantity("Gamma") == r"$\Gamma = \eta_0 U_0 / (G W)$"
    assert quantity("end:min_m1") == "min $m_1$ at the end of the branch"
    assert quantity("min_m1@0.1", "Wi") == "min $m_1$ at Wi = 0.1"
    assert quantity("event:min_m1", "Wi") == "Wi where min $m_1$ = 0"
    assert quantity("event:fold", "lambda") == r"$\lambda$ at the fold"
    assert quantity("bratu.intervals") == "intervals" and quantity("sigma1_re") == r"Re $\sigma_{1}$"
    # every parameter and observable of keller's problems has its label
    for name in ("Wi", "Gamma", "t", "Pe", "Re", "beta", "b", "alpha", "epsilon", "xi", "inertia", "lambda", "mu",
                 "dP", "dP_inlet_outlet", "dx_max", "dy_max", "gap_min", "min_m1", "min_m1_x", "min_m1_y", "max_m3",
                 "K", "K_surface", "K_devss", "eta", "eta_p", "eta_e", "eta_e_p", "N1", "N2", "psi1_p", "M_xx",
                 "M_xy", "M_yy", "M_zz", "Wi_local", "rate", "log10_rate", "u_mid", "u_max", "u_min", "u_mean",
                 "u_norm", "u_centre", "u_quarter", "v_mean"):
        assert name in QUANTITIES, name


def run_quietly(kind, *words):
    """Runs a figure module's main in this process, warnings as errors, its output swallowed."""
    module = importlib.import_module(kind if "." in kind else f"keller.plot.{kind}")
    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()), \
            contextlib.redirect_stderr(io.StringIO()):
        warnings.simplefilter("error")
        return module.main([str(w) for w in words])


@pytest.fixture(scope="module")
def cylinder_branch(run):
    """Three steps of the Oldroyd-B cylinder on its coarsest mesh (a few seconds)."""
    run("trace", run.scene("cylinder_oldroyd_b.toml"), "-o", "cyl.h5", "--set", "mesh.name=C1", "--set",
        "continuation.max_steps=3", "--set", "output.xdmf=false")
    return run.path("cyl.h5")


def test_every_figure_module_without_a_warning(bratu_branch, pitchfork_branch, fold_curve, time_series,
                                                study_folder, channel_branch, cylinder_branch, tmp_path, run):
    run("trace", run.scene("steady_shear_ptt.toml"), "-o", "shear_w.h5", "--set", "output.xdmf=false")
    out = str(tmp_path)
    for kind, words in (
            ("branch", [bratu_branch, "--y", "u_mid", "--footer", "--title", "t"]),
            ("branch", [pitchfork_branch, "--y", "u_quarter", "--values"]),
            ("branch", [fold_curve, "--y", "lambda"]),
            ("collapsible", [channel_branch, "--footer"]),
            ("field", [channel_branch, "--field", "velocity:vx"]),
            ("flow", [channel_branch]),
            ("evolve", [time_series, "--log"]),
            ("study", [study_folder, "--x", "bratu.intervals", "--y", "event:fold"]),
            ("rheometry", [run.path("shear_w.h5")]),
            ("interfaces", ["--newtonian", channel_branch, channel_branch]),
            ("cylinder_drag", [cylinder_branch]),
            ("cylinder_deviation", [cylinder_branch]),
            ("keller.mesh_convergence", [bratu_branch, bratu_branch, "--observables", "u_mid"]),
            ("keller.convergence", [os.path.join(study_folder, "s.h5"), "--mesh", "bratu.intervals",
                                    "--resolution", "bratu.intervals", "--observables", "event:fold",
                                    "end:u_mid", "--mark-unsettled"])):
        name = f"{kind}_{len(os.listdir(out))}"
        target = os.path.join(out, name + (".png" if kind != "collapsible" else ""))
        flag = "--figure" if kind.startswith("keller.") else "-o"
        assert run_quietly(kind, *words, flag, target) in (None, 0), kind
        assert os.path.exists(target if kind != "collapsible" else target + "_branch.png"), kind
