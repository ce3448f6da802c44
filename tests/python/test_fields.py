"""The fields of stored states and the mesh they live on, against the same file read by h5py: a
collapsible-channel branch on a coarse mesh (its moving mesh: the fields' `position` is where the
nodes are) and one solved state of it. Every field of every stored solution is the file's
dataset with its components; the mesh of a state is on its deformed positions; its triangles
(8 per 9-node element) are not inverted; the P1-discontinuous pressure at an element's centre
node is its centre value."""

import h5py
import numpy as np

import keller
from keller.files.h5 import text


def same(a, b):
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape, (a.shape, b.shape)
    assert np.array_equal(a, b, equal_nan=True)


def datasets(group):
    return {n: group[n] for n in group if isinstance(group[n], h5py.Dataset)}


def test_every_field_of_every_stored_solution(channel_branch):
    b = keller.open(channel_branch)
    assert b.parameter == "t" and b.status == "reached the lower bound t = 0.1"
    with h5py.File(channel_branch, "r") as f:
        groups = {int(f["branch/fields"][g].attrs["row"]): f["branch/fields"][g] for g in f["branch/fields"]}
        assert sorted(groups) == [s.row for s in b.solutions]
        for s in b.solutions:
            g = groups[s.row]
            assert s.value == g.attrs["t"]
            stored = datasets(g)
            assert sorted(s.fields) == sorted(stored)
            for name, d in stored.items():
                field = s.fields[name]
                same(field, d[()])
                assert field.components == text(d.attrs.get("components", d.attrs.get("columns", ""))).split(",")
                assert field.basis == text(d.attrs.get("basis", ""))
            same(s.field("velocity", "vx"), g["velocity"][:, 0])
            same(s.field("pressure", "p"), g["pressure"][:, 0])
            assert s.fields["pressure"].basis == "P1disc" and s.fields["velocity"].groups == ["fluid"]


def test_the_mesh_of_a_state_is_deformed(channel_branch):
    b = keller.open(channel_branch)
    with h5py.File(channel_branch, "r") as f:
        elements, groups = f["mesh/elements"][()], f["mesh/element_group"][()]
        names = [text(n) for n in f["mesh/group_names"][()]]
        moved = 0
        for s in b.solutions:
            position = next(f["branch/fields"][k]["position"][()] for k in f["branch/fields"]
                            if int(f["branch/fields"][k].attrs["row"]) == s.row)
            m = s.mesh
            same(m.nodes, position)
            same(m.elements, elements)
            same(m.element_group, groups)
            assert m.group_names == names
            assert sorted(m.boundaries) == sorted(f["mesh/boundaries"])
            for name, edges in m.boundaries.items():
                same(edges, f["mesh/boundaries"][name][()])
            same(s.undeformed_nodes(), position - s.fields["displacement"])
            moved += not np.array_equal(m.nodes, f["mesh/nodes"][()])
        assert moved > 0  # the wall moves along the branch: the states' meshes differ from /mesh/nodes


def test_triangles_and_the_nodal_pressure(channel_branch):
    s = keller.open(channel_branch).solutions[-1]
    m = s.mesh
    fluid = m.group_names.index("fluid")
    assert m.elements.shape[1] == 9 and int(np.sum(m.element_group == fluid)) == 80  # 20 x 4 fluid elements
    tri = s.triangulation("fluid")
    assert tri.triangles.shape == (640, 3)
    x, y = m.nodes[tri.triangles, 0], m.nodes[tri.triangles, 1]
    area = 0.5 * ((x[:, 1] - x[:, 0]) * (y[:, 2] - y[:, 0]) - (x[:, 2] - x[:, 0]) * (y[:, 1] - y[:, 0]))
    assert area.min() > 0.0
    assert m.triangles().shape == (8 * len(m.elements), 3)
    # the triangles of an element are its 3 x 3 node grid's four quads, each cut once
    first = m.elements_of("fluid")[0]
    assert sorted(set(tri.triangles[:8].ravel())) == sorted(first)
    pressure, nodal = s.fields["pressure"], s.nodal_pressure()
    for e in np.flatnonzero(m.element_group == fluid):
        assert nodal[m.elements[e, 4]] == pressure[e, 0]
    off_fluid = np.setdiff1d(np.arange(len(m.nodes)), m.elements_of("fluid").ravel())
    assert len(off_fluid) > 0 and np.all(np.isnan(nodal[off_fluid]))


def test_a_solved_state_on_its_deformed_mesh(channel_solve):
    s = keller.open(channel_solve)
    assert isinstance(s, keller.Solution)
    with h5py.File(channel_solve, "r") as f:
        stored = datasets(f["solution/fields"])
        assert sorted(s.fields) == sorted(stored)
        for name, d in stored.items():
            same(s.fields[name], d[()])
        same(s.mesh.nodes, f["solution/fields/position"][()])
        same(s.u, f["solution/u"][()])
        assert s.observables == dict(f["solution/observables"].attrs)
        assert s.parameters == dict(f["solution/parameters"].attrs)
        n = f["solution/newton"]
        names = text(n.attrs["columns"]).split(",")
        assert s.newton.columns == names and len(s.newton) == n.shape[0] > 0
        for i, c in enumerate(names):
            same(s.newton[c], n[:, i])
    assert s.stability is None and s.unstable is None and s.eigenvalues is None
    assert "conformation" in s.fields or "conformation_M" in s.fields  # Oldroyd-B


def test_the_critical_modes_as_fields(channel_modes):
    b = keller.open(channel_modes)
    with h5py.File(channel_modes, "r") as f:
        rows = f["branch/eigenvector_rows"][()]
        vectors = f["branch/eigenvectors"][()]
        by_row = {s.row: s for s in b.solutions}
        checked = 0
        for k, (row, _, re_, im) in enumerate(rows):
            s = by_row[int(row)]
            assert s.sigma == complex(re_, im)
            np.testing.assert_array_equal(s.eigenvector, vectors[2 * k] + 1j * vectors[2 * k + 1])
            g = f[f"branch/modes/{k}"]
            assert int(g.attrs["row"]) == s.row
            assert sorted(s.mode_fields) == sorted(p for p in ("re", "im") if p in g)
            for part, fields in s.mode_fields.items():
                stored = datasets(g[part])
                assert sorted(fields) == sorted(stored) and "velocity" in fields
                for name, d in stored.items():
                    same(fields[name], d[()])
            checked += 1
        assert checked > 0
