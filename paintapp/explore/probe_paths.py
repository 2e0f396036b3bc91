"""Scripted probe paths for ``paintapp explore --path PATH.csv``: where the probe is, when.

A path is CSV text with a header row naming its columns, then one row per keyframe:

- ``t_s`` (seconds, non-decreasing), ``x_m``, ``y_m`` and, for a 3D data set, ``z_m`` (metres,
  in the data set's frame);
- optionally the orientation: ``angle_rad`` (2D, counter-clockwise) or ``qw, qx, qy, qz``
  (3D, a quaternion, normalised here).

Between keyframes the pose is linear (orientation: angle linear, quaternions slerped). Every
problem is an :class:`~common.errors.InputError` naming the file, line and column.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from common import quaternion
from common.errors import InputError
from common.limits import read_text_capped

#: Most keyframes a path may hold.
MAX_ROWS = 1_000_000
#: Most bytes of a path file.
MAX_BYTES = 64 * 1024**2


@dataclass(frozen=True)
class ProbePath:
    """Keyframes: times (n,), positions (n, dim), orientations (n,) angles or (n, 4) quaternions."""

    times_s: np.ndarray
    positions_m: np.ndarray
    orientations: np.ndarray
    source: str = ""

    @property
    def dim(self) -> int:
        return int(self.positions_m.shape[1])

    def pose_at(self, t_s: float) -> tuple[np.ndarray, np.ndarray | float]:
        """Position (dim,) and orientation (angle or (4,) quaternion) at ``t_s`` (clamped)."""
        times = self.times_s
        if t_s <= times[0] or len(times) == 1:
            return self.positions_m[0].copy(), self._orientation(0)
        if t_s >= times[-1]:
            return self.positions_m[-1].copy(), self._orientation(len(times) - 1)
        i = int(np.searchsorted(times, t_s, side="right")) - 1
        span = times[i + 1] - times[i]
        a = 0.0 if span <= 0 else (t_s - times[i]) / span
        pos = (1 - a) * self.positions_m[i] + a * self.positions_m[i + 1]
        if self.dim == 2:
            return pos, float((1 - a) * self.orientations[i] + a * self.orientations[i + 1])
        return pos, quaternion.slerp(self.orientations[i], self.orientations[i + 1], a)

    def _orientation(self, i: int) -> np.ndarray | float:
        return float(self.orientations[i]) if self.dim == 2 else self.orientations[i].copy()


def read_probe_path(path: str | Path, dim: int) -> ProbePath:
    """Read and validate a path for a ``dim``-dimensional data set."""
    source = str(path)
    try:
        text = read_text_capped(path, MAX_BYTES, "path file")
    except FileNotFoundError:
        raise InputError("no such path file", source=source) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read the path file: {exc}", source=source) from None
    reader = csv.reader(io.StringIO(text))
    try:
        rows = list(reader)
    except csv.Error as exc:
        raise InputError(f"not valid CSV: {exc}", source=source, line=reader.line_num) from None
    if not rows:
        raise InputError("the path file is empty; expected a header row", source=source, line=1)
    header = [c.strip() for c in rows[0]]
    columns = _columns(header, dim, source)
    body = [(n, r) for n, r in enumerate(rows[1:], start=2) if any(c.strip() for c in r)]
    if not body:
        raise InputError("the path has no keyframes", source=source, line=2)
    if len(body) > MAX_ROWS:
        raise InputError(f"the path has {len(body)} rows; at most {MAX_ROWS}", source=source)
    values = np.empty((len(body), len(header)))
    for k, (line, row) in enumerate(body):
        if len(row) != len(header):
            raise InputError(f"expected {len(header)} values, got {len(row)}", source, line=line)
        for c, (name, cell) in enumerate(zip(header, row, strict=True)):
            try:
                v = float(cell)
            except ValueError:
                raise InputError(
                    f"expected a number, got {cell.strip()!r}", source, name, line
                ) from None
            if not math.isfinite(v) or abs(v) > 1e9:
                raise InputError(
                    f"expected a finite number of at most 1e9, got {cell.strip()}",
                    source,
                    name,
                    line,
                )
            values[k, c] = v
    times = values[:, header.index("t_s")]
    back = np.flatnonzero(np.diff(times) < 0)
    if len(back):
        raise InputError("time goes backwards", source, "t_s", body[back[0] + 1][0])
    positions = values[:, [header.index(c) for c in columns["position"]]]
    orientations = _orientations(values, header, columns, dim, source, [n for n, _ in body])
    return ProbePath(times, positions, orientations, source)


def _columns(header: list[str], dim: int, source: str) -> dict[str, list[str]]:
    position = ["x_m", "y_m", "z_m"][:dim]
    orient = ["angle_rad"] if dim == 2 else ["qw", "qx", "qy", "qz"]
    allowed = {"t_s", *position, *orient}
    for name in header:
        if header.count(name) > 1:
            raise InputError("column given twice", source, name, 1)
        if name not in allowed:
            raise InputError(
                f"unknown column; expected t_s, {', '.join(position)} and optionally "
                f"{', '.join(orient)}",
                source,
                name,
                1,
            )
    for name in ("t_s", *position):
        if name not in header:
            raise InputError("missing column", source, name, 1)
    given = [c for c in orient if c in header]
    if given and len(given) != len(orient):
        raise InputError(f"give all of {', '.join(orient)} or none", source, given[0], 1)
    return {"position": position, "orientation": given}


def _orientations(
    values: np.ndarray,
    header: list[str],
    columns: dict[str, list[str]],
    dim: int,
    source: str,
    lines: list[int],
) -> np.ndarray:
    n = len(values)
    if not columns["orientation"]:
        return np.zeros(n) if dim == 2 else np.tile([1.0, 0.0, 0.0, 0.0], (n, 1))
    cols = [header.index(c) for c in columns["orientation"]]
    if dim == 2:
        return values[:, cols[0]].copy()
    q = values[:, cols]
    norms = np.linalg.norm(q, axis=1)
    bad = np.flatnonzero(norms < 1e-9)
    if len(bad):
        raise InputError("expected a non-zero quaternion", source, "qw", lines[bad[0]])
    return q / norms[:, None]
