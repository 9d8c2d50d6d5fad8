"""Output: time series (CSV and SVG plots drawn by the library) and ParaView files."""

import csv
import ctypes
import os
from typing import TYPE_CHECKING, Any, List, Mapping, Optional, Sequence, Tuple, Union

from ._errors import check, check_path
from ._lib import SeriesPtr, VtuArray, lib
from .context import _Handle

if TYPE_CHECKING:  # pragma: no cover
    from .context import Context
    from .particles import Particles

PathLike = Union[str, bytes, "os.PathLike[str]", "os.PathLike[bytes]"]


class Series(_Handle):
    """A time series of named, unit-carrying columns (sinter_series).

        series = sinter.Series(ctx, [("time", "s"), ("temperature", "K")])
        series.append([0.0, 300.0])
        series.write_csv("t.csv")
        series.write_svg("t.svg", panels=[[1]], title="particle")
    """

    _destroy_function = "sinter_series_destroy"

    def __init__(self, context: "Context",
                 columns: Sequence[Union[str, Tuple[str, str]]]) -> None:
        """A series of `columns`: names, or (name, unit) pairs (unit \"1\" by default)."""
        columns = [(c, "1") if isinstance(c, str) else tuple(c) for c in columns]
        if not columns:
            raise ValueError("a series needs at least one column")
        names = (ctypes.c_char_p * len(columns))(*[n.encode("utf-8") for n, _ in columns])
        units = (ctypes.c_char_p * len(columns))(*[u.encode("utf-8") for _, u in columns])
        handle = SeriesPtr()
        check(lib.sinter_series_create(ctypes.byref(handle), context._ptr, len(columns), names,
                                       units),
              context._handle, "sinter_series_create")
        super().__init__(context, handle)
        self.columns = [name for name, _ in columns]
        self.units = [unit for _, unit in columns]

    @classmethod
    def read_csv(cls, context: "Context", path: PathLike) -> "Series":
        """Read a series back from a CSV file written by write_csv or by a run (names and
        units from the header, every complete row). FileNotFoundError when `path` does not
        exist; SinterError ERR_PARSE naming the line for a malformed file."""
        handle = SeriesPtr()
        check_path(lib.sinter_series_read_csv(ctypes.byref(handle), context._ptr,
                                              os.fsencode(path)),
                   context._handle, "sinter_series_read_csv", path)
        series = cls.__new__(cls)
        _Handle.__init__(series, context, handle)
        names, units = [], []
        header = _csv_header(path)
        for column in header:
            name, bracket, unit = column.rpartition(" [")
            if bracket and unit.endswith("]"):
                names.append(name)
                units.append(unit[:-1])
            else:
                names.append(column)
                units.append("")
        series.columns, series.units = names, units
        return series

    def append(self, row: Sequence[float]) -> None:
        """Append one row of len(columns) numbers (NaN allowed)."""
        row = [float(x) for x in row]
        if len(row) != len(self.columns):
            raise ValueError("a row of this series has %d values, got %d"
                             % (len(self.columns), len(row)))
        self._check(lib.sinter_series_append(self._ptr, (ctypes.c_double * len(row))(*row)),
                    "sinter_series_append")

    @property
    def rows(self) -> int:
        """Number of rows."""
        rows = ctypes.c_size_t()
        self._check(lib.sinter_series_rows(self._ptr, ctypes.byref(rows)), "sinter_series_rows")
        return rows.value

    def __len__(self) -> int:
        return self.rows

    def _column_index(self, column):
        if isinstance(column, str):
            try:
                return self.columns.index(column)
            except ValueError:
                raise KeyError("no column %r; columns: %s" % (column, self.columns)) from None
        return int(column)

    def get(self, row: int, column: Union[int, str]) -> float:
        """Value at (row, column), the column by index or name."""
        value = ctypes.c_double()
        self._check(lib.sinter_series_get(self._ptr, int(row), self._column_index(column),
                                          ctypes.byref(value)),
                    "sinter_series_get")
        return value.value

    def __getitem__(self, index: Any) -> Any:
        """series[row, column] (column by index or name), or series["name"] for a whole column."""
        if isinstance(index, tuple):
            return self.get(*index)
        return self.column(index)

    def column(self, column: Union[int, str]) -> List[float]:
        """All values of a column (by index or name), as a list."""
        k = self._column_index(column)
        return [self.get(row, k) for row in range(self.rows)]

    def write_csv(self, path: PathLike) -> None:
        """CSV: a header "name [unit],..." then one line per row, full precision."""
        self._check(lib.sinter_series_write_csv(self._ptr, os.fsencode(path)),
                    "sinter_series_write_csv")

    def write_svg(self, path: PathLike,
                  panels: Optional[Sequence[Sequence[Union[int, str]]]] = None,
                  x_column: Union[int, str] = 0, title: Optional[str] = None) -> None:
        """SVG plot: one panel per entry of `panels` (lists of columns, by index or name)
        against x_column; by default one panel with every other column."""
        x = self._column_index(x_column)
        if panels is None:
            panels = [[k for k in range(len(self.columns)) if k != x]]
        start, flat = [0], []
        for panel in panels:
            flat.extend(self._column_index(c) for c in panel)
            start.append(len(flat))
        c_start = (ctypes.c_size_t * len(start))(*start)
        c_flat = (ctypes.c_size_t * max(len(flat), 1))(*flat)
        self._check(lib.sinter_series_write_svg(self._ptr, os.fsencode(path),
                                                None if title is None else title.encode("utf-8"),
                                                x, len(panels), c_start, c_flat),
                    "sinter_series_write_svg")

    def __repr__(self) -> str:
        return "<sinter.Series %s>" % ("closed" if self.closed else "%s, %d rows" % (
            self.columns, self.rows))


def _csv_header(path):
    """The column titles "name [unit]" of a series CSV file's first line."""
    with open(path, encoding="utf-8", errors="replace", newline="") as lines:
        return next(csv.reader(lines), [])


def write_vtu(particles: "Particles", path: PathLike,
              extra: Optional[Mapping[str, Any]] = None) -> None:
    """One ParaView frame (.vtu) of a particle set; `extra` maps names to per-particle arrays
    (count values, or count x 3)."""
    extra = dict(extra or {})
    count = particles.count
    arrays, keep = [], []
    for name, values in extra.items():
        if hasattr(values, "tolist"):  # NumPy array or memoryview
            values = values.tolist()
        rows = [list(v) if isinstance(v, (list, tuple)) else [v] for v in values]
        if len(rows) != count:
            raise ValueError("extra array %r has %d rows for %d particles"
                             % (name, len(rows), count))
        components = len(rows[0]) if rows else 1
        if components not in (1, 3) or any(len(r) != components for r in rows):
            raise ValueError("extra array %r needs 1 or 3 components per particle" % name)
        flat = [float(x) for r in rows for x in r]
        data = (ctypes.c_double * max(len(flat), 1))(*flat)
        keep.append(data)
        arrays.append(VtuArray(name.encode("utf-8"), ctypes.cast(data, ctypes.POINTER(
            ctypes.c_double)), components))
    c_arrays = (VtuArray * max(len(arrays), 1))(*arrays)
    particles._check(lib.sinter_write_vtu(particles._ptr, os.fsencode(path),
                                          c_arrays if arrays else None, len(arrays)),
                     "sinter_write_vtu")


def write_pvd(context: "Context", path: PathLike, times: Sequence[float],
              files: Sequence[PathLike]) -> None:
    """A ParaView collection (.pvd) of `files` (as they should appear in it) at `times` [s]."""
    times, files = [float(t) for t in times], [os.fsencode(f) for f in files]
    if len(times) != len(files):
        raise ValueError("%d times but %d files" % (len(times), len(files)))
    c_times = (ctypes.c_double * max(len(times), 1))(*times)
    c_files = (ctypes.c_char_p * max(len(files), 1))(*files)
    check(lib.sinter_write_pvd(context._ptr, os.fsencode(path), len(times), c_times, c_files),
          context._handle, "sinter_write_pvd")


def plot_run(context: "Context", out_dir: PathLike, title: Optional[str] = None) -> None:
    """Draw out_dir/series.svg from out_dir/series.csv, as a run does at its end (any run,
    finished or not)."""
    status = lib.sinter_plot_run(context._ptr, os.fsencode(out_dir),
                                 None if title is None else title.encode("utf-8"))
    if status != 0 and os.path.isdir(out_dir):
        check_path(status, context._handle, "sinter_plot_run",
                   os.path.join(os.fsdecode(out_dir), "series.csv"))
    check_path(status, context._handle, "sinter_plot_run", out_dir, directory=True)


def plot_csv(context: "Context", csv_path: PathLike, svg_path: PathLike,
             panels: Sequence[str] = (), x: Optional[str] = None,
             title: Optional[str] = None) -> None:
    """Draw chosen columns of any CSV a run writes (series.csv, frames/profile_z_NNNNN.csv)
    into svg_path: one panel per entry of `panels`, each a comma-separated list of column
    names (without units) or prefixes ("coordination"), against the column `x` (None: the
    first). No panels: every column, one panel each (8 at most)."""
    names = [p.encode("utf-8") for p in panels]
    array = (ctypes.c_char_p * max(len(names), 1))(*names)
    status = lib.sinter_plot_csv(context._ptr, os.fsencode(csv_path), os.fsencode(svg_path),
                                 None if title is None else title.encode("utf-8"),
                                 None if x is None else x.encode("utf-8"), array, len(names))
    check_path(status, context._handle, "sinter_plot_csv", csv_path)
