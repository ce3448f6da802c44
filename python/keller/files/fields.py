"""Fields of a stored state (/solution/fields, /branch/fields/<slot>, /evolve/fields/<slot>) and
the mesh they live on (/mesh): each field a numpy array that also carries its basis and component
names, the mesh on the deformed positions where the state has a `position` field (the
collapsible channel's moving mesh), its triangles for matplotlib, and the P1-discontinuous
pressure evaluated at the nodes."""

import numpy as np

from keller.files.h5 import attributes, names, open_h5, text


class Field(np.ndarray):
    """A stored field: a numpy array (nodal: nodes x components, NaN where the field does not
    live; P1disc: elements x 3 per component; a 1D problem's profile: a table) with `basis`
    ('Q2', 'Q1', 'P1disc' or '' for a table), `components` (its column names: `vx,vy` or
    `x,u`), `groups` (the element groups it lives on) and `doc` (what it is, where stored)."""

    def __new__(cls, values, attrs):
        obj = np.asarray(values).view(cls)
        obj.attrs = dict(attrs)
        obj.basis = text(attrs.get("basis", ""))
        obj.components = names(attrs.get("components", attrs.get("columns", "")))
        obj.groups = names(attrs.get("groups", ""))
        obj.doc = text(attrs.get("doc", ""))
        return obj

    def __array_finalize__(self, obj):
        for a, default in (("attrs", {}), ("basis", ""), ("components", []), ("groups", []), ("doc", "")):
            setattr(self, a, getattr(obj, a, default))

    def component(self, name):
        """The column of one component (`vx`, `u`) as a plain array; KeyError naming the ones it has."""
        if name not in self.components:
            raise KeyError(f"no component '{name}'; it has: {', '.join(self.components)}")
        values = np.asarray(self)
        if self.basis == "P1disc":  # element x (3 * component): the centre values of each
            return values[:, 3 * self.components.index(name)]
        return values.reshape(len(values), -1)[:, self.components.index(name)]


def read_fields(group):
    """{name: Field} of the datasets of an open fields group (its `xdmf` copies left out)."""
    import h5py

    return {name: Field(group[name][()], attributes(group[name]))
            for name in group if isinstance(group[name], h5py.Dataset)}


class Mesh:
    """A mesh of 9-node quadrilaterals (/mesh): `nodes` (N x 2: the positions of a state where it
    has a `position` field, else /mesh/nodes), `elements` (E x 9, lexicographic: node i + 3 j at
    reference (s_i, t_j)), `element_group` (per element), `group_names`, `boundaries` ({name:
    (element, edge) rows})."""

    def __init__(self, nodes, elements, element_group, group_names, boundaries):
        self.nodes, self.elements = nodes, elements
        self.element_group, self.group_names, self.boundaries = element_group, group_names, boundaries

    @classmethod
    def read(cls, f, nodes=None):
        """The mesh of an open file, on `nodes` where given; None where the file has none (a 1D
        problem's)."""
        if "mesh" not in f:
            return None
        m = f["mesh"]
        boundaries = {n: np.array(m["boundaries"][n][()], dtype=int) for n in m["boundaries"]} \
            if "boundaries" in m else {}
        return cls(np.array(m["nodes"][()]) if nodes is None else np.asarray(nodes),
                   np.array(m["elements"][()], dtype=int), np.array(m["element_group"][()], dtype=int),
                   [text(n) for n in m["group_names"][()]], boundaries)

    def elements_of(self, group=None):
        """The elements of one group (`fluid`, `solid`), all where group is None."""
        if group is None:
            return self.elements
        if group not in self.group_names:
            raise KeyError(f"no element group '{group}'; the mesh has: {', '.join(self.group_names)}")
        return self.elements[self.element_group == self.group_names.index(group)]

    def triangles(self, group=None):
        """Each 9-node quadrilateral (of a group, or all) split into 8 triangles through its
        mid-side nodes: (8 E) x 3 node indices."""
        els = self.elements_of(group)
        if len(els) == 0:
            return np.zeros((0, 3), dtype=int)
        quads = [(i + 3 * j, i + 1 + 3 * j, i + 3 * (j + 1), i + 1 + 3 * (j + 1)) for j in range(2) for i in range(2)]
        local = np.array([t for a, b, c, d in quads for t in ((a, b, d), (a, d, c))])
        return els[:, local].reshape(-1, 3)

    def triangulation(self, group=None):
        """A matplotlib Triangulation of the nodes and triangles (group: `fluid`, say)."""
        import matplotlib.tri as mtri  # here: reading arrays and tables needs no matplotlib

        return mtri.Triangulation(self.nodes[:, 0], self.nodes[:, 1], self.triangles(group))

    def nodal_pressure(self, pressure):
        """A P1-discontinuous field (E x 3: c0 + c1 (x - xc) + c2 (y - yc), xc the centre node)
        evaluated at each element's nodes on these positions; nodes shared by elements get the
        last element's value (enough for a contour picture); NaN at nodes of no element where
        it lives."""
        pc = np.asarray(pressure)
        pn = np.full(len(self.nodes), np.nan)
        for e, el in enumerate(self.elements):
            if np.isnan(pc[e, 0]):
                continue
            xc = self.nodes[el[4]]
            pn[el] = pc[e, 0] + pc[e, 1] * (self.nodes[el, 0] - xc[0]) + pc[e, 2] * (self.nodes[el, 1] - xc[1])
        return pn


class State:
    """A state stored in a file: its vector `u` and, where the file has them, its `fields` and
    `mesh` (on the deformed positions where there is a `position` field), read when first
    asked for. fields_group: the HDF5 path of its fields (None: none stored)."""

    def __init__(self, path, fields_group, u_path=None, u_index=None):
        self.path, self.fields_group = path, fields_group
        self._u_path, self._u_index = u_path, u_index
        self._fields = self._mesh = self._u = None

    @property
    def u(self):
        """The state vector (the unknowns as the problem orders them)."""
        if self._u is None and self._u_path is not None:
            with open_h5(self.path) as f:
                d = f[self._u_path]
                self._u = np.array(d[()] if self._u_index is None else d[self._u_index])
        return self._u

    @property
    def fields(self):
        """{name: Field} ({} where the file stores none for this state: a branch whose run was
        killed before it wrote them, which `keller export FILE --xdmf` adds)."""
        if self._fields is None:
            self._fields = {}
            if self.fields_group:
                with open_h5(self.path) as f:
                    if self.fields_group in f:
                        self._fields = read_fields(f[self.fields_group])
        return self._fields

    @property
    def mesh(self):
        """The Mesh of the state, its nodes at the `position` field where there is one; None for a
        file without a mesh."""
        if self._mesh is None:
            with open_h5(self.path) as f:
                self._mesh = Mesh.read(f, self.fields.get("position"))
        return self._mesh

    def field(self, name, component=None):
        """A field (or one component of it as a plain array); KeyError naming the fields there."""
        if name not in self.fields:
            raise KeyError(f"{self.path}: the stored state has no field '{name}'; its fields: "
                           f"{', '.join(self.fields) or 'none'}")
        return self.fields[name] if component is None else self.fields[name].component(component)

    def undeformed_nodes(self):
        """The node positions less the displacement (where the state has both fields), else the
        file's /mesh/nodes."""
        if "position" in self.fields and "displacement" in self.fields:
            return np.asarray(self.fields["position"]) - np.asarray(self.fields["displacement"])
        with open_h5(self.path) as f:
            return np.array(f["mesh/nodes"][()])

    def triangulation(self, group="fluid"):
        """The triangulation of the deformed mesh (of one element group; all where the mesh has
        no such group)."""
        m = self.mesh
        return m.triangulation(group if group in m.group_names else None)

    def nodal_pressure(self, name="pressure"):
        """The P1disc pressure at the nodes of the deformed mesh (Mesh.nodal_pressure)."""
        return self.mesh.nodal_pressure(self.field(name))
