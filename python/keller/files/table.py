"""A table of named columns (a branch's, a time series', a study's), read the way a data frame is:
`table["Wi"]` is a column (a numpy array), `table.columns` their names in the file's order,
`len(table)` the number of rows, iterating it gives the column names."""

import numpy as np


class Table:
    """Named numpy columns of equal length, in the order the file lists them."""

    def __init__(self, columns):
        """columns: {name: 1D array}, in order."""
        self._columns = dict(columns)
        lengths = {len(v) for v in self._columns.values()}
        if len(lengths) > 1:
            raise ValueError(f"columns of different lengths: {sorted(lengths)}")
        self._rows = lengths.pop() if lengths else 0

    @classmethod
    def from_rows(cls, names, rows):
        """The table of a 2D float array whose columns are `names` (as a keller table is
        stored: one row per point)."""
        rows = np.asarray(rows, dtype=float).reshape(-1, len(names))
        return cls({c: rows[:, i] for i, c in enumerate(names)})

    @property
    def columns(self):
        """The column names, in the file's order."""
        return list(self._columns)

    def __getitem__(self, name):
        try:
            return self._columns[name]
        except KeyError:
            raise KeyError(f"no column '{name}'; the columns: {', '.join(self._columns)}") from None

    def __contains__(self, name):
        return name in self._columns

    def __iter__(self):
        return iter(self._columns)

    def __len__(self):
        return self._rows

    def keys(self):
        return self._columns.keys()

    def values(self):
        return self._columns.values()

    def items(self):
        return self._columns.items()

    def get(self, name, default=None):
        return self._columns.get(name, default)

    def row(self, i):
        """{column: value} of row i."""
        return {c: v[i] for c, v in self._columns.items()}

    def take(self, index):
        """A table of the rows `index` selects (an index array or a boolean mask)."""
        return Table({c: v[index] for c, v in self._columns.items()})

    def sorted_by(self, column):
        """The rows in the order of a column (stable). A branch's rows by `s` are its points in
        their order along the branch: a change located by bisection is written after rows that
        lie beyond it."""
        return self.take(np.argsort(self[column], kind="stable"))

    def to_records(self):
        """The table as a numpy structured array (one record per row)."""
        return np.rec.fromarrays(list(self._columns.values()), names=list(self._columns))

    def __repr__(self):
        return f"Table({self._rows} rows: {', '.join(self._columns)})"


class TableView:
    """What a file object with a `table` (a Table) reads like: `obj["column"]`, `column in obj`,
    `len(obj)` (its rows) and `obj.columns`."""

    @property
    def columns(self):
        return self.table.columns

    def __getitem__(self, column):
        return self.table[column]

    def __contains__(self, column):
        return column in self.table

    def __len__(self):
        return len(self.table)
