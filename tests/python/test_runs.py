"""keller's commands from Python (keller.trace, solve, evolve, study; python/keller/runs.py) against
the command line: the same files row by row, a callback that stops a run, bad input, exceptions.
Environment: KELLER_EXE (the keller program), KELLER_SOURCE (the source tree), PYTHONPATH with the
build's python folder (ctest sets them)."""

import os
import subprocess
import sys

import h5py
import numpy as np
import pytest

import keller

SOURCE = os.environ["KELLER_SOURCE"]
KELLER = os.environ["KELLER_EXE"]
BRATU = os.path.join(SOURCE, "runs", "scenes", "bratu1d_fold.toml")
# A fixed renewal cost: by default the corrector measures what a factorisation costs in wall time
# along the run (continuation.renewal_cost = 0), so two runs of the same command (from Python or
# not) can take a new Jacobian at different iterations and differ at the location tolerance (1e-8 in
# s in one of six command-line runs); with it fixed, every run is the same to the last bit.
FIXED = {"continuation.renewal_cost": 3.0}


def table(path):
    """{column: values} of a branch or time-series file read by h5py, without the wall times."""
    with h5py.File(path, "r") as f:
        group = f["branch"] if "branch" in f else f["evolve"]
        columns = group.attrs["columns"]
        columns = (columns.decode() if isinstance(columns, bytes) else str(columns)).split(",")
        rows = np.array(group["table"][()]).reshape(-1, len(columns))
    return {c: rows[:, i] for i, c in enumerate(columns) if c != "seconds"}


def status(path):
    with h5py.File(path, "r") as f:
        s = f["branch/status"][()]
    return (s.decode() if isinstance(s, bytes) else str(s)).rstrip("\x00")


def test_trace_from_python_is_the_command_lines_row_by_row(tmp_path):
    # the same BLAS kernels as this process: the keller program would pick the CPU's own where
    # OpenBLAS fell back to Prescott's (docs/performance.md, "BLAS kernels"), which round otherwise
    same_kernels = dict(os.environ, KELLER_BLAS_KERNELS="keep")
    subprocess.run([KELLER, "trace", BRATU, "-o", str(tmp_path / "cli.h5"), "--set", "continuation.renewal_cost=3.0"],
                   check=True, capture_output=True, env=same_kernels)
    branch = keller.trace(BRATU, tmp_path / "py.h5", set=FIXED, verbose=False)
    assert isinstance(branch, keller.Branch)
    cli, py = table(tmp_path / "cli.h5"), table(tmp_path / "py.h5")
    assert list(cli) == list(py)
    for column in cli:  # the same computation in the same order: equal to the last bit
        np.testing.assert_array_equal(py[column], cli[column], err_msg=column)
    # and the object reads the same file
    np.testing.assert_array_equal(branch["lambda"], py["lambda"])


def test_a_scene_dict_and_overrides_are_the_files(tmp_path):
    import tomllib
    with open(BRATU, "rb") as f:
        scene = tomllib.load(f)
    scene["bratu"]["intervals"] = 64
    scene["continuation"]["renewal_cost"] = 3.0
    from_dict = keller.trace(scene, tmp_path / "dict.h5", verbose=False)
    from_file = keller.trace(BRATU, tmp_path / "file.h5", set={"bratu.intervals": 64, **FIXED}, verbose=False)
    a, b = table(from_dict.path), table(from_file.path)
    for column in a:
        np.testing.assert_array_equal(a[column], b[column], err_msg=column)


def test_a_callback_sees_every_point_and_stopping_leaves_a_restartable_file(tmp_path):
    full = keller.trace(BRATU, tmp_path / "full.h5", set=FIXED, verbose=False)
    seen = []

    def stop_after_five(point):
        seen.append((point.row, point.kind, point["lambda"], point["u_mid"]))
        assert point.u.shape == (127,)
        return point.row < 5

    out = tmp_path / "stopped.h5"
    stopped = keller.trace(BRATU, out, set=FIXED, callback=stop_after_five, verbose=False)
    assert stopped.path.endswith("stopped.h5.part") and not out.exists()
    assert status(stopped.path).startswith("interrupted")
    rows = table(stopped.path)
    whole = table(full.path)
    assert len(rows["row"]) == 6  # rows 0..5: everything completed before the stop
    for column in rows:
        np.testing.assert_array_equal(rows[column], whole[column][:6], err_msg=column)
    assert [s[0] for s in seen] == list(range(6))
    np.testing.assert_array_equal([s[2] for s in seen], whole["lambda"][:6])
    # the same call continues it to the end: the fold and the end where the whole run has them
    continued = keller.trace(BRATU, out, set=FIXED, callback=lambda p: seen.append(p.row), verbose=False)
    assert continued.path == str(out) and out.exists()
    assert seen[6] > 5  # the continuation's points only
    assert abs(continued.point("fold1")["lambda"] - full.point("fold1")["lambda"]) < 1e-10
    assert abs(continued.point("end")["lambda"] - full.point("end")["lambda"]) < 1e-10


def test_an_exception_in_a_callback_stops_the_run_and_is_raised(tmp_path):
    def fails(point):
        if point.row == 3:
            raise ZeroDivisionError("the callback's own error")

    with pytest.raises(ZeroDivisionError, match="the callback's own error"):
        keller.trace(BRATU, tmp_path / "x.h5", callback=fails, verbose=False)
    assert len(table(tmp_path / "x.h5.part")["row"]) == 4  # kept, to be continued


def test_bad_input_is_a_keller_error_naming_the_key_and_writes_nothing(tmp_path):
    with pytest.raises(keller.KellerError) as e:
        keller.trace(BRATU, tmp_path / "bad.h5", set={"continuation.max_step": -1.0}, verbose=False)
    assert e.value.code == 2 and "continuation.max_step" in str(e.value)
    with pytest.raises(keller.KellerError) as e:
        keller.trace({"problem": {"type": "bratu1d"}, "bratu": {"intervalls": 4}}, tmp_path / "bad.h5", verbose=False)
    assert e.value.code == 2 and "intervalls" in str(e.value) and "the scene dict" in str(e.value)
    assert os.listdir(tmp_path) == []


def test_solve_and_evolve_return_their_files(tmp_path):
    solution = keller.solve(BRATU, tmp_path / "s.h5", set={"bratu.lambda": 2.0}, verbose=False)
    assert isinstance(solution, keller.Solution)
    with h5py.File(tmp_path / "s.h5", "r") as f:
        np.testing.assert_array_equal(solution.u, f["solution/u"][()])
    steps = []
    series = keller.evolve(os.path.join(SOURCE, "runs", "scenes", "brusselator1d_evolve.toml"), tmp_path / "e.h5",
                           set={"evolve.t_end": 2.0}, callback=lambda p: steps.append((p.row, p["t"])), verbose=False)
    assert isinstance(series, keller.TimeSeries)
    rows = table(tmp_path / "e.h5")
    np.testing.assert_array_equal([s[0] for s in steps], rows["step"])
    np.testing.assert_array_equal([s[1] for s in steps], rows["t"])


def test_ctrl_c_stops_after_the_current_point_keeps_the_file_and_raises_keyboard_interrupt(tmp_path):
    """SIGINT while a trace runs in a Python process: the run stops as the command line's does and
    the call raises KeyboardInterrupt; the same call continues the branch."""
    import signal
    import sys
    code = f"""
import sys, time, keller
def slow(point):
    print("row", point.row, flush=True)
    time.sleep(0.2)
try:
    keller.trace({BRATU!r}, {str(tmp_path / 'c.h5')!r}, callback=slow, verbose=False)
    print("finished", flush=True)
except KeyboardInterrupt as e:
    print("KeyboardInterrupt:", e, flush=True)
"""
    child = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True, env=dict(os.environ))
    lines = []
    for line in child.stdout:
        lines.append(line)
        if line.startswith("row 3"):
            child.send_signal(signal.SIGINT)
    child.wait(timeout=60)
    assert child.returncode == 0
    assert lines[-1].startswith("KeyboardInterrupt: keller trace interrupted"), lines
    rows = table(tmp_path / "c.h5.part")["row"]
    assert 4 <= len(rows) <= 5  # row 3 and at most the point in progress
    assert status(tmp_path / "c.h5.part").startswith("interrupted")
    branch = keller.trace(BRATU, tmp_path / "c.h5", verbose=False)  # the same call continues it
    full = keller.trace(BRATU, tmp_path / "full.h5", verbose=False)
    assert abs(branch.point("fold1")["lambda"] - full.point("fold1")["lambda"]) < 1e-10


def test_a_study_from_python_is_the_command_lines(tmp_path):
    """keller.study runs its tasks as processes of the keller program (this process is Python's)
    and collects the same table as `keller study`."""
    study_file = tmp_path / "s.toml"
    study_file.write_text(f'[study]\nscene = "{BRATU}"\n\n[set]\n"output.xdmf" = false\n"continuation.renewal_cost" = 3.0\n\n'
                          '[grid]\n"bratu.intervals" = [16, 32]\n\n[collect]\nevents = ["fold"]\nend = ["u_mid"]\n')
    study = keller.study(study_file, tmp_path / "py", jobs=2, verbose=False)
    subprocess.run([KELLER, "study", str(study_file), "-o", str(tmp_path / "cli"), "--jobs", "2"], check=True,
                   capture_output=True)
    assert isinstance(study, keller.Study)
    with h5py.File(tmp_path / "cli" / "s.h5", "r") as f:
        cli_fold = np.array(f["study"]["event:fold"][()])
    with h5py.File(tmp_path / "py" / "s.h5", "r") as f:
        py_fold = np.array(f["study"]["event:fold"][()])
    # the same tasks in processes of the same program, with a fixed renewal cost (FIXED)
    np.testing.assert_array_equal(py_fold, cli_fold)
    # the branches' folds: 16 and 32 intervals
    np.testing.assert_array_equal(study.table["event:fold"], py_fold)
    assert len(py_fold) == 2 and np.all(np.abs(py_fold - 3.51) < 0.01)


def test_a_run_leaves_the_blas_threads_as_numpy_has_them(tmp_path):
    """keller's command line takes one OpenBLAS thread for small matrices (core/BlasThreads.hpp); the
    package turns that off, since numpy may share the process's OpenBLAS. OpenBLAS is loaded into
    the global scope first, where keller's lookup would find it, so that a package that left the
    policy on would set one thread here."""
    if len(os.sched_getaffinity(0)) < 2:
        pytest.skip("one CPU: OpenBLAS starts with one thread")
    code = f"""
import ctypes, sys
try:
    blas = ctypes.CDLL("libopenblas.so.0", mode=ctypes.RTLD_GLOBAL)
except OSError:
    print("no OpenBLAS")
    sys.exit(0)
import keller
before = blas.openblas_get_num_threads()
keller.trace({BRATU!r}, {str(tmp_path / "b.h5")!r}, verbose=False)
print(before, blas.openblas_get_num_threads())
"""
    env = dict(os.environ, OPENBLAS_NUM_THREADS="2")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True)
    if out.stdout.strip() == "no OpenBLAS":
        pytest.skip("the BLAS is not OpenBLAS")
    assert out.stdout.split()[-2:] == ["2", "2"], out.stdout + out.stderr
