"""keller.open on files keller writes, each object against the same file read by h5py directly
(every number equal: the package must hand over the file's data, not a copy that drifts), the
kinds against `keller export --csv`, the labels against `keller info`: a branch, its located
points and stored solutions; a branch with [stability]; a fold curve; a time series; a solve file
with its spectrum; a study; a branch whose run was killed (its .part file, open only in SWMR
mode); the scene and the provenance."""

import csv
import os
import re
import subprocess
import tomllib

import h5py
import numpy as np
import pytest

import keller
import keller.results
from keller.files.h5 import text


def h5(path):
    """The file as h5py opens a file of a run that may have been killed."""
    try:
        return h5py.File(path, "r")
    except OSError:
        return h5py.File(path, "r", swmr=True)


def same(a, b):
    """Equal arrays, NaN equal to NaN, nothing else allowed to differ."""
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape, (a.shape, b.shape)
    assert np.array_equal(a, b, equal_nan=a.dtype.kind in "fc"), (a, b)


def info_labels(run, path):
    """[(label, row)] of the `located points:` line of keller info."""
    out = run("info", path).stdout
    line = next(l for l in out.splitlines() if l.startswith("located points:"))
    return [(m.group(1), int(m.group(2))) for m in re.finditer(r"(\w+) \(row (\d+)\)", line)]


def check_table(obj, f, group):
    """The object's table is the HDF5 table, column by column, in the file's order."""
    names = text(f[group].attrs["columns"]).split(",")
    rows = np.array(f[group]["table"][()]).reshape(-1, len(names))
    assert obj.columns == names
    assert len(obj) == rows.shape[0]
    for i, c in enumerate(names):
        same(obj.table[c], rows[:, i])
        same(obj[c], rows[:, i])


def check_common(obj, f):
    """The scene, the provenance, /problem and its parameters as the file stores them."""
    assert obj.scene_text == text(f["scene"][()])
    assert obj.scene == tomllib.loads(text(f["scene"][()]))
    stored = f["provenance"].attrs
    assert obj.provenance == {k: (text(v) if isinstance(v, (bytes, str)) else v) for k, v in stored.items()}
    assert obj.parameters == {k: float(v) for k, v in f["problem/parameters"].attrs.items()}
    assert obj.problem["name"] == text(f["problem"].attrs["name"])


def test_a_branch_its_table_kinds_labels_and_points(run, bratu_branch):
    b = keller.open(bratu_branch)
    assert isinstance(b, keller.Branch) and not isinstance(b, keller.Curve)
    with h5(bratu_branch) as f:
        assert b.parameter == text(f["branch"].attrs["parameter"]) == "lambda"
        check_table(b, f, "branch")
        check_common(b, f)
        assert b.status == text(f["branch/status"][()])
        assert b.exit_code == int(f["branch/exit_code"][()].ravel()[0]) == 0
        assert b.observables == text(f["branch"].attrs["observables"]).split(",")
        # the kinds by the names of the file's own `kinds` attribute ('0 point, 1 start, ...')
        names = dict(item.split(" ") for item in text(f["branch"].attrs["kinds"]).split(", "))
        assert list(b.kinds) == [names[str(int(k))] for k in f["branch/table"][:, 1]]
    # ... and as keller export --csv names them
    b_csv = os.path.join(os.path.dirname(bratu_branch), "bratu.csv")
    run("export", bratu_branch, "--csv", b_csv)
    with open(b_csv, newline="") as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == b.columns
    assert list(b.kinds) == [r[rows[0].index("kind")] for r in rows[1:]]
    # the labels are keller info's, and name the rows of their kinds
    assert b.labels == info_labels(run, bratu_branch)
    assert [lab for lab, _ in b.labels] == ["start", "stop1", "stop2", "stop3", "fold1", "stop4", "stop5", "end"]
    folds = b.points("fold")
    assert [p.row for p in folds] == [int(r) for r, k in zip(b["row"], b["kind"]) if k == 4]
    fold = b.point("fold1")
    assert fold.label == "fold1" and fold.kind == "fold" and b.point("fold").row == fold.row
    assert fold.value == b["lambda"][fold.index] and fold["u_mid"] == b["u_mid"][fold.index]
    assert fold.solution is not None and fold.solution.row == fold.row
    assert [p.label for p in b.points()] == [lab for lab, _ in b.labels]
    assert b.point(fold.row).label == "fold1" and b.point(str(fold.row)).row == fold.row
    assert b.point("last").row == b.solutions[-1].row
    with pytest.raises(KeyError, match="no located point labelled 'hopf1'; its labels: start \\(row 0\\)"):
        b.point("hopf1")


def test_stored_solutions_of_a_branch(bratu_branch):
    b = keller.open(bratu_branch)
    with h5(bratu_branch) as f:
        saved = f["branch/saved"][()]
        groups = {int(f["branch/fields"][g].attrs["row"]): f["branch/fields"][g] for g in f["branch/fields"]}
        assert [s.row for s in b.solutions] == sorted(int(r) for r in saved[:, 0])
        for s in b.solutions:
            k = s.slot
            assert (s.row, s.value, s.tangent_parameter, s.step, s.s) == tuple(saved[k, [0, 2, 3, 4, 5]])
            assert s.kind == keller.results.KINDS[int(saved[k, 1])]
            same(s.u, f["branch/solutions"][k])
            same(s.tangent, f["branch/tangents"][k])
            g = groups[s.row]
            assert sorted(s.fields) == sorted(n for n in g if isinstance(g[n], h5py.Dataset))
            same(s.fields["profile"], g["profile"][()])
            assert s.fields["profile"].components == ["x", "u"]
            same(s.field("profile", "u"), g["profile"][:, 1])
            assert s.mesh is None  # a 1D problem has no /mesh
        # the saved_slot column points at the stored solution of its row
        for i in np.flatnonzero(b["saved_slot"] >= 0):
            assert b.solution_at(int(b["row"][i])).slot == int(b["saved_slot"][i])


def test_a_branch_with_stability(run, pitchfork_branch):
    b = keller.open(pitchfork_branch)
    with h5(pitchfork_branch) as f:
        check_table(b, f, "branch")
        names = text(f["branch"].attrs["columns"]).split(",")
        table = f["branch/table"][()]
        same(b.unstable, table[:, names.index("unstable")])
        k = sum(1 for c in names if re.fullmatch(r"sigma\d+_re", c))
        assert b.eigenvalues.shape == (len(table), k) == (len(table), 4)
        for j in range(k):
            same(b.eigenvalues[:, j].real, table[:, names.index(f"sigma{j + 1}_re")])
            same(b.eigenvalues[:, j].imag, table[:, names.index(f"sigma{j + 1}_im")])
        er, ev = f["branch/eigenvector_rows"][()], f["branch/eigenvectors"][()]
        by_row = {s.row: s for s in b.solutions}
        assert len(er) > 0
        for i, (row, _, re_, im) in enumerate(er):
            s = by_row[int(row)]
            assert s.sigma == complex(re_, im)
            same(s.eigenvector, ev[2 * i] + 1j * ev[2 * i + 1])
            # the mode as fields: a 1D problem's are empty groups, as the file has them
            g = f[f"branch/modes/{i}"]
            assert sorted(s.mode_fields) == sorted(g)
            for part in g:
                assert sorted(s.mode_fields[part]) == sorted(n for n in g[part] if isinstance(g[part][n], h5py.Dataset))
    assert b.labels == info_labels(run, pitchfork_branch)
    assert [p.label for p in b.points("bp")] == ["bp1", "bp2"]
    # the discrete eigenvalues lambda_k = (4 / h^2) sin^2(k pi h / 2) of the scene's header
    assert b.point("bp1").value == pytest.approx(9.867622767, abs=1e-8)
    assert b.point("bp2").value == pytest.approx(39.44671910, abs=1e-7)


def test_a_fold_curve(run, fold_curve):
    c = keller.open(fold_curve)
    assert isinstance(c, keller.Curve)
    with h5(fold_curve) as f:
        check_table(c, f, "branch")
        assert c.curve == text(f["problem"].attrs["curve"]) == "fold"
        assert c.curve_from == text(f["problem"].attrs["curve_from"]) == "shifted.h5:fold1"
        assert (c.parameter, c.second_parameter) == ("mu", "lambda")
        names = text(f["branch"].attrs["columns"]).split(",")
        same(c[c.second_parameter], f["branch/table"][:, names.index("lambda")])
    assert run("info", fold_curve).stdout.splitlines()[0].endswith("a fold curve in (mu, lambda) (keller trace "
                                                                       "--curve), from shifted.h5:fold1")
    assert c.labels == info_labels(run, fold_curve)


def test_a_time_series(time_series):
    t = keller.open(time_series)
    assert isinstance(t, keller.TimeSeries)
    with h5(time_series) as f:
        check_table(t, f, "evolve")
        check_common(t, f)
        assert t.status == text(f["evolve/status"][()]) == "reached t_end"
        assert t.exit_code == 0
        m = f["evolve_start/mode"]
        assert t.mode.sigma == complex(m.attrs["sigma_re"], m.attrs["sigma_im"])
        same(t.mode.vector, m[0] + 1j * m[1])
        same(t.start_state, f["evolve_start/state"][()])
        saved = f["evolve/saved"][()]
        assert [(s.step, s.t) for s in t.states] == [(int(a), b) for a, b in saved]
        groups = {int(f["evolve/fields"][g].attrs["step"]): f["evolve/fields"][g] for g in f["evolve/fields"]}
        for s in t.states:
            same(s.u, f["evolve/solutions"][s.slot])
            same(s.fields["profile"], groups[s.step]["profile"][()])
            assert s.fields["profile"].components == ["x", "u", "v"]
        ring, index = t.history()
        same(ring, f["evolve/history"][()])
        same(index, f["evolve/history_index"][()])
    assert t["t"][-1] == 3.0
    # the k = 0 mode of the uniform state: -(b - 1 - a^2) / 2 = -0.1 (the scene's header)
    assert t.mode.sigma.real == pytest.approx(-0.1, abs=1e-9)


def test_a_solve_file_with_its_spectrum(solve_file):
    s = keller.open(solve_file)
    assert isinstance(s, keller.Solution)
    with h5(solve_file) as f:
        check_common(s, f)
        same(s.u, f["solution/u"][()])
        assert s.parameters == dict(f["solution/parameters"].attrs) == {"eps": 0.0, "lambda": 20.0}
        assert s.observables == dict(f["solution/observables"].attrs)
        n = f["solution/newton"]
        assert s.newton.columns == text(n.attrs["columns"]).split(",")
        assert len(s.newton) == n.shape[0]
        st = f["solution/stability"]
        assert s.stability.columns == ["sigma_re", "sigma_im", "residual"]
        same(s.stability["sigma_re"], st[:, 0])
        same(s.eigenvalues, st[:, 0] + 1j * st[:, 1])
        assert s.unstable == int(st.attrs["unstable"]) == 1
        same(s.fields["profile"], f["solution/fields/profile"][()])
    # one eigenvalue below zero: lambda_1 - 20 of the discrete problem
    assert s.eigenvalues[0].real == pytest.approx(9.867622767 - 20.0, abs=1e-7)


def test_a_study_its_table_and_its_branches(study_folder):
    s = keller.open(study_folder)
    assert isinstance(s, keller.Study)
    assert s.path == os.path.join(study_folder, "s.h5")
    assert keller.open(s.path).table.columns == s.table.columns
    with h5(s.path) as f:
        order = text(f["study"].attrs["columns"]).split(",")
        assert s.columns == order
        for c in order:
            v = f["study"][c][()]
            if v.dtype.kind in "SO":
                assert list(s[c]) == [text(x) for x in v]
            else:
                same(s[c], v)
        assert s.provenance["keller_version"] == text(f["provenance"].attrs["keller_version"])
    # numbers are numbers, text is text
    assert s["event:fold"].dtype.kind == "f" and s["status"].dtype.kind == "U"
    assert list(s["status"]) == ["done", "done"] and s.status == {"done": 2}
    # a task's branch, by name, index or varied value
    i = s.rows({"bratu.intervals": 32})
    assert len(i) == 1
    b = s.branch({"bratu.intervals": 32})
    assert b.path == os.path.join(study_folder, "tasks", s["name"][i[0]] + ".h5")
    assert s.branch(i[0]).path == b.path == s.branch(s["name"][i[0]]).path
    assert b.point("fold1").value == s.value("event:fold", {"bratu.intervals": 32})
    assert b["u_mid"][-1] == s["end:u_mid"][i[0]]
    assert keller.results.same_value("32", 32) and not keller.results.same_value("32", 32.1)


def test_a_killed_runs_file_opens_in_swmr_mode(run, killed_branch):
    b = keller.open(killed_branch)
    assert b.status == "running" and b.exit_code is None
    with h5py.File(killed_branch, "r", swmr=True) as f:
        check_table(b, f, "branch")
        assert len(b) >= 5
        assert [s.row for s in b.solutions] == sorted(int(r) for r in f["branch/saved"][:, 0])
        for s in b.solutions:
            same(s.u, f["branch/solutions"][s.slot])
            assert s.fields == {}  # the fields are written once the branch has ended
    assert b.labels == info_labels(run, killed_branch)


def test_provenance_is_the_keller_that_wrote_the_file(keller_exe, bratu_branch):
    b = keller.open(bratu_branch)
    version = subprocess.run([keller_exe, "--version"], capture_output=True, text=True).stdout
    assert b.provenance["keller_version"] in version and b.provenance["commit"] in version
    assert b.provenance["command_line"].startswith(keller_exe + " trace ")
    assert b.scene["continuation"]["parameter"] == "lambda" and b.scene["continuation"]["stops"] == [1.0, 2.0, 3.0]


def test_what_is_not_a_keller_file(tmp_path):
    with pytest.raises(FileNotFoundError):
        keller.open(tmp_path / "none.h5")
    with h5py.File(tmp_path / "other.h5", "w") as f:
        f["x"] = 1
    with pytest.raises(ValueError, match="not a file keller writes"):
        keller.open(tmp_path / "other.h5")
