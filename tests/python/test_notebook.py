"""docs/python_tour.ipynb executed as a user would (nbclient, Debian's python3-nbclient and
ipykernel) in a scratch folder: it runs without an error and its numbers are right (the branch
points at the grid's closed form, the limiting Wi's state with min m1 = 0)."""

import os
import re

import nbclient
import nbformat

SOURCE = os.environ["KELLER_SOURCE"]


def test_the_tour_runs_and_finds_the_closed_forms(tmp_path, monkeypatch):
    nb = nbformat.read(os.path.join(SOURCE, "docs", "python_tour.ipynb"), as_version=4)
    monkeypatch.setenv("PYDEVD_DISABLE_FILE_VALIDATION", "1")
    monkeypatch.delenv("MPLBACKEND", raising=False)  # the kernel's own inline backend, as in Jupyter
    nbclient.NotebookClient(nb, timeout=600, kernel_name="python3",
                            resources={"metadata": {"path": str(tmp_path)}}).execute()
    text = "".join(o.get("text", "") for c in nb.cells if c.cell_type == "code" for o in c.outputs)
    images = sum("image/png" in o.get("data", {}) for c in nb.cells if c.cell_type == "code" for o in c.outputs)
    assert images == 3
    pairs = re.findall(r"bp\d: lambda = ([\d.]+), closed form ([\d.]+), unstable eigenvalues after it: (\d)", text)
    assert len(pairs) == 2
    for located, closed, _ in pairs:
        assert abs(float(located) - float(closed)) < 1e-10 * float(closed)
    assert [int(p[2]) for p in pairs] == [1, 3]  # a simple, then a double eigenvalue crosses
    assert abs(float(re.search(r"smallest m1 on the mesh: (\S+)", text).group(1))) < 1e-8
    assert os.path.exists(tmp_path / "tour" / "curve.h5")
