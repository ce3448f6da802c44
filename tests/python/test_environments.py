"""The package under a python3 that is not Debian's: a virtual environment that sees Debian's
packages runs the README's commands; one without them fails with the message that names what is
missing and the command that installs it (keller/__init__.py)."""

import os
import subprocess
import sys

import pytest

SOURCE = os.environ["KELLER_SOURCE"]
KELLER = os.environ["KELLER_EXE"]


def venv(folder, system_packages):
    """A virtual environment of this Python (no pip: nothing is downloaded), its python."""
    args = [sys.executable, "-m", "venv", "--without-pip", str(folder)]
    if system_packages:
        args.insert(4, "--system-site-packages")
    subprocess.run(args, check=True, capture_output=True)
    return str(folder / "bin" / "python")


def test_a_venv_with_the_system_packages_runs_the_readme_commands(tmp_path):
    python = venv(tmp_path / "with", True)
    env = dict(os.environ, PYTHONPATH=os.environ["PYTHONPATH"])
    scene = os.path.join(SOURCE, "runs", "scenes", "bratu1d_fold.toml")
    subprocess.run([KELLER, "trace", scene, "-o", str(tmp_path / "b.h5")], check=True, capture_output=True)
    done = subprocess.run([python, "-m", "keller.plot", "branch", str(tmp_path / "b.h5"), "--y", "u_max", "-o",
                           str(tmp_path / "b.png")], env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert os.path.getsize(tmp_path / "b.png") > 10000
    # and a run in its process
    code = ("import keller; b = keller.trace(%r, %r, verbose=False); print(round(b.point('fold1')['lambda'], 8))"
            % (scene, str(tmp_path / "c.h5")))
    done = subprocess.run([python, "-c", code], env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "3.51371914"


@pytest.mark.parametrize("command", [["-c", "import keller"], ["-m", "keller.plot", "branch", "x.h5", "-o", "x.png"]])
def test_a_venv_without_them_says_what_is_missing_and_how_to_install_it(tmp_path, command):
    python = venv(tmp_path / "without", False)
    done = subprocess.run([python] + command, env=dict(os.environ), capture_output=True, text=True, cwd=tmp_path)
    assert done.returncode != 0
    assert "keller needs the Python modules numpy, scipy, h5py, matplotlib" in done.stderr
    assert f"{python} -m pip install numpy scipy h5py matplotlib" in done.stderr
    assert "apt-get install python3-numpy python3-scipy python3-h5py python3-matplotlib" in done.stderr
    assert not os.path.exists(tmp_path / "x.png")
