"""The figures of the package (python3 -m keller.plot KIND, keller.convergence,
keller.mesh_convergence) on files keller writes: each kind draws its figure from the files alone;
the labels name only the scene keys that tell files apart; a figure never replaces an input; bad
input is refused without a figure."""

import csv
import os
import subprocess
import sys

import pytest

from keller.labels import distinguishing_labels, quantity


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
    assert quantity("time_") == "time_" and quantity("Wi") == "Wi (inlet Weissenberg number)"


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
