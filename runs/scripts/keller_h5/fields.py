"""The fields of the solutions stored on a branch (/branch/fields/<group>) and the mesh they live
on (/mesh), as numpy arrays and matplotlib triangulations."""

import numpy as np

from keller_h5.h5 import open_h5, text


def read_array(path, group, name):
    """The field `name` of the stored solution `group`, or None where it has none."""
    with open_h5(path) as f:
        g = f["branch/fields"][group]
        return np.array(g[name][()]) if name in g else None


def read_mesh(path):
    """(9-node elements, element group index per element, group names) of the mesh (/mesh)."""
    with open_h5(path) as f:
        elements = np.array(f["mesh/elements"][()], dtype=int)
        groups = np.array(f["mesh/element_group"][()], dtype=int)
        names = [text(n) for n in f["mesh/group_names"][()]]
    return elements, groups, names


def triangulation(path, group):
    """Triangles of the deformed fluid mesh (each 9-node quad split into 8) and node positions."""
    import matplotlib.tri as mtri  # here: reading arrays and tables needs no matplotlib

    elements, groups, names = read_mesh(path)
    pos = read_array(path, group, "position")
    fluid = elements[groups == names.index("fluid")]
    tris = []
    for el in fluid:  # lexicographic 3x3 node grid
        for j in range(2):
            for i in range(2):
                a, b, c, d = el[i + 3 * j], el[i + 1 + 3 * j], el[i + 3 * (j + 1)], el[i + 1 + 3 * (j + 1)]
                tris += [(a, b, d), (a, d, c)]
    return mtri.Triangulation(pos[:, 0], pos[:, 1], np.array(tris)), fluid, pos


def nodal_pressure(path, group, pos):
    """The P1-discontinuous pressure of a stored solution evaluated at each element's nodes (pos:
    the deformed node positions); nodes shared by elements get the last value (enough for a
    contour picture); NaN at nodes of no fluid element."""
    pc = read_array(path, group, "pressure")
    pn = np.full(len(pos), np.nan)
    elements, _, _ = read_mesh(path)
    for e, el in enumerate(elements):
        if np.isnan(pc[e, 0]):
            continue
        xc = pos[el[4]]
        pn[el] = pc[e, 0] + pc[e, 1] * (pos[el, 0] - xc[0]) + pc[e, 2] * (pos[el, 1] - xc[1])
    return pn
