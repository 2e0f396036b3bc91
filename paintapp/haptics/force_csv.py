"""Force traces as CSV: a header row naming the columns, then one row of numbers per servo tick.

:data:`DEVICE_COLUMNS` are what the servo loop writes to the device: time in s, then force x, y, z
in N and torque x, y, z in N m. A replay's trace holds those; an exploration's adds the fluid's own
force and torque beside them (:mod:`paintapp.explore.force_trace`).
"""

from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np

from common.errors import InputError
from paintapp.atomic import atomic_path

#: The device's columns of a force trace.
DEVICE_COLUMNS = (
    "time_s",
    "force_x_n",
    "force_y_n",
    "force_z_n",
    "torque_x_nm",
    "torque_y_nm",
    "torque_z_nm",
)


def write_trace_csv(path: str | Path, columns: tuple[str, ...], rows: np.ndarray) -> None:
    """Write ``rows`` (ticks, len(columns)) under the header ``columns``, atomically; a
    non-finite value is a ValueError (nothing is written)."""
    rows = np.asarray(rows, dtype=float).reshape(-1, len(columns))
    if not np.all(np.isfinite(rows)):
        raise ValueError("a force trace must be finite")
    out = io.StringIO()
    out.write(",".join(columns) + "\n")
    for row in rows:
        out.write(",".join(f"{v:.9g}" for v in row) + "\n")
    with atomic_path(path) as tmp:
        tmp.write_text(out.getvalue(), encoding="utf-8")


def read_trace_csv(path: str | Path, columns: tuple[str, ...]) -> np.ndarray:
    """The rows (ticks, len(columns)) of a file :func:`write_trace_csv` wrote with
    ``columns``; :class:`InputError` on a malformed file."""
    source = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8")
    except OSError as exc:
        raise InputError(f"cannot read the forces file: {exc}", source) from None
    rows = list(csv.reader(io.StringIO(text)))
    if not rows or tuple(rows[0]) != columns:
        raise InputError(f"expected the header {','.join(columns)}", source, line=1)
    try:
        data = np.array([[float(v) for v in row] for row in rows[1:]], dtype=float)
    except ValueError as exc:
        raise InputError(f"expected numbers: {exc}", source) from None
    return data.reshape(-1, len(columns))
