"""Branch files of `keller trace`: the branch table and the solutions stored on it."""

from keller_h5.h5 import open_h5, read_table, text

# the kind column of a branch table (/branch attribute kinds)
KINDS = {0: "point", 1: "start", 2: "requested", 3: "event", 4: "fold", 5: "branch point", 6: "end", 7: "Hopf"}


def read_branch(path):
    """Returns (parameter name, {column: array}, status) of a branch file."""
    with open_h5(path) as f:
        columns, status = read_table(f["branch"])
        return text(f["branch"].attrs["parameter"]), columns, status


def saved_solutions(path):
    """[(parameter value, table row, group name)] of the solutions whose fields are stored
    (/branch/fields, written by `keller trace` or `keller export`), in branch order."""
    parameter, _, _ = read_branch(path)
    with open_h5(path) as f:
        if "branch/fields" not in f:
            return []
        out = []
        for name in f["branch/fields"]:
            g = f["branch/fields"][name]
            out.append((float(g.attrs[parameter]), int(g.attrs["row"]), name))
        return sorted(out, key=lambda t: t[1])
