"""Fixtures of the Python package's tests: the keller under test (env KELLER_EXE), the source tree
(env KELLER_SOURCE) and the files the tests read, each made once per test session by running a
small scene of runs/scenes in a scratch folder (the coarse or fast ones: seconds in all).

ctest runs each test file as its own test (tests/CMakeLists.txt, label `python`) with PYTHONPATH
at the build's python folder; by hand, from the repository:

    KELLER_EXE=build/bin/keller KELLER_SOURCE=. PYTHONPATH=build/python python3 -m pytest -q tests/python"""

import os
import signal
import subprocess
import time

import h5py
import pytest

# the collapsible channel on a coarse mesh (20 x 4 fluid elements, 2 solid rows): a second
COARSE_CHANNEL = ["--set", "mesh.name=custom", "--set", "mesh.nx_upstream=5", "--set", "mesh.nx_deformable=10",
                  "--set", "mesh.nx_downstream=5", "--set", "mesh.ny_fluid=4", "--set", "mesh.ny_solid=2"]


def _env(name):
    value = os.environ.get(name)
    if not value:
        pytest.fail(f"the environment variable {name} is not set (conftest.py says how the tests run)")
    return os.path.abspath(value)


@pytest.fixture(scope="session")
def keller_exe():
    return _env("KELLER_EXE")


@pytest.fixture(scope="session")
def source():
    return _env("KELLER_SOURCE")


@pytest.fixture(scope="session")
def scratch(tmp_path_factory):
    return tmp_path_factory.mktemp("keller")


class Keller:
    """Runs the keller under test in the scratch folder."""

    def __init__(self, exe, source, folder):
        self.exe, self.source, self.folder = exe, source, folder

    def scene(self, name):
        return os.path.join(self.source, "runs", "scenes", name)

    def __call__(self, *words, check=True):
        p = subprocess.run([self.exe, *map(str, words)], cwd=self.folder, capture_output=True, text=True,
                           env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
        if check and p.returncode != 0:
            raise AssertionError(f"keller {' '.join(map(str, words))}: exit {p.returncode}\n{p.stdout}\n{p.stderr}")
        return p

    def path(self, name):
        return str(self.folder / name)


@pytest.fixture(scope="session")
def run(keller_exe, source, scratch):
    return Keller(keller_exe, source, scratch)


@pytest.fixture(scope="session")
def bratu_branch(run):
    """The 1D Bratu problem round its fold (stops, a fold, the end at the stop observable)."""
    run("trace", run.scene("bratu1d_fold.toml"), "-o", "bratu.h5")
    return run.path("bratu.h5")


@pytest.fixture(scope="session")
def pitchfork_branch(run):
    """The pitchfork's trivial branch with [stability]: two branch points, unstable counts,
    eigenvalue columns and the critical eigenvectors."""
    run("trace", run.scene("pitchfork1d_trivial.toml"), "-o", "pitchfork.h5")
    return run.path("pitchfork.h5")


@pytest.fixture(scope="session")
def fold_curve(run):
    """A fold curve in (mu, lambda) from the fold of the shifted Bratu branch."""
    scene = run.scene("bratu1d_shifted_fold_curve.toml")
    run("trace", scene, "-o", "shifted.h5")
    run("trace", scene, "-o", "curve.h5", "--from", "shifted.h5:fold1", "--curve", "fold", "--free", "mu")
    return run.path("curve.h5")


@pytest.fixture(scope="session")
def time_series(run):
    """The Brusselator beyond its Hopf point, perturbed along the critical mode, to t = 3."""
    run("evolve", run.scene("brusselator1d_evolve.toml"), "--set", "evolve.t_end=3", "-o", "evolve.h5")
    return run.path("evolve.h5")


@pytest.fixture(scope="session")
def solve_file(run):
    """One steady state with its spectrum: u = 0 of the pitchfork at lambda = 20 (one unstable
    eigenvalue, 20 - lambda_1 of the discrete problem)."""
    run("solve", run.scene("pitchfork1d_trivial.toml"), "--set", "parameters.lambda=20", "-o", "solve.h5")
    return run.path("solve.h5")


@pytest.fixture(scope="session")
def channel_branch(run):
    """A collapsible-channel branch in the wall thickness on a coarse mesh, with the fields of its
    stored solutions on the deformed mesh."""
    run("trace", run.scene("collapsible_newtonian_thickness.toml"), "-o", "channel.h5", *COARSE_CHANNEL)
    return run.path("channel.h5")


@pytest.fixture(scope="session")
def channel_solve(run):
    """One state of the collapsible channel (coarse mesh): a solve file with a deformed mesh."""
    run("solve", run.scene("collapsible_oldroyd_b.toml"), "-o", "channel_solve.h5", *COARSE_CHANNEL)
    return run.path("channel_solve.h5")


@pytest.fixture(scope="session")
def study_folder(run):
    """A study of two Bratu branches (16 and 32 intervals) collecting the fold and u_mid at the end."""
    with open(run.path("s.toml"), "w") as f:
        f.write(f'[study]\nscene = "{run.scene("bratu1d_fold.toml")}"\n\n[set]\n"output.xdmf" = false\n\n'
                '[grid]\n"bratu.intervals" = [16, 32]\n\n[collect]\nevents = ["fold"]\nend = ["u_mid"]\n')
    run("study", "s.toml", "--jobs", "1", "-o", "study")
    return run.path("study")


@pytest.fixture(scope="session")
def killed_branch(run):
    """A branch whose run was killed (SIGKILL) after its fifth point: its OUT.h5.part, written in
    SWMR mode and never closed. The 2D Bratu problem on 48 x 48 with small steps takes seconds a
    branch, long enough to be killed part way."""
    out = run.path("killed.h5")
    p = subprocess.Popen([run.exe, "trace", run.scene("bratu2d_fold.toml"), "-o", out, "--set",
                          "output.xdmf=false", "--set", "bratu.intervals=48", "--set", "continuation.max_step=0.01",
                          "--set", "continuation.initial_step=0.01"], cwd=run.folder, stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL, env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
    part, deadline = out + ".part", time.monotonic() + 60
    try:
        while time.monotonic() < deadline and p.poll() is None:
            try:
                with h5py.File(part, "r", swmr=True) as f:
                    if f["branch/table"].shape[0] >= 5:
                        break
            except (OSError, KeyError):
                pass
            time.sleep(0.05)
    finally:
        if p.poll() is None:
            p.send_signal(signal.SIGKILL)
        p.wait()
    if p.returncode != -signal.SIGKILL or not os.path.exists(part):
        pytest.fail(f"the run was not killed part way (exit {p.returncode})")
    return part


@pytest.fixture(scope="session")
def channel_modes(run):
    """One step of an Oldroyd-B Gamma branch on a tiny channel mesh with [stability]: the critical
    eigenvector of each stored point, and its mode as fields (/branch/modes/<k>)."""
    run("trace", run.scene("collapsible_oldroyd_b_gamma.toml"), "-o", "modes.h5", "--set", "mesh.name=custom",
        "--set", "mesh.nx_upstream=3", "--set", "mesh.nx_deformable=6", "--set", "mesh.nx_downstream=3",
        "--set", "mesh.ny_fluid=3", "--set", "mesh.ny_solid=1", "--set", "stability.enabled=true",
        "--set", "continuation.max_steps=1")
    return run.path("modes.h5")
