"""An append-only log of what the servo loop did each tick, cheap enough for 1 kHz.

Rows go into preallocated chunks, so appending never copies earlier data and nothing recorded is
lost if the loop stops on a device failure. :meth:`TickLog.save` writes an ``.npz`` (plain
arrays, no pickled objects).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

# Column layout of one row: name -> (first column, width).
COLUMNS: dict[str, tuple[int, int]] = {
    "t_s": (0, 1),
    "position_m": (1, 3),
    "velocity_m_per_s": (4, 3),
    "contact_force_n": (7, 3),
    "fluid_force_n": (10, 3),
    "fluid_torque_nm": (13, 3),
    "force_n": (16, 3),
    "torque_nm": (19, 3),
}
WIDTH = 22
_CHUNK = 4096


class TickLog:
    """Per-tick records: time, tip state, force components and the force actually written.

    ``force_n``/``torque_nm`` are what was written to the device (after safety);
    ``contact_force_n``, ``fluid_force_n`` and ``fluid_torque_nm`` are the commanded parts.
    Positions are in the device frame (the published states are in the canvas frame).
    """

    def __init__(self) -> None:
        self._chunks: list[np.ndarray] = []
        self._row = _CHUNK

    def next_row(self) -> np.ndarray:
        """A writable row of width :data:`WIDTH` for the next tick (filled by the caller)."""
        if self._row == _CHUNK:
            self._chunks.append(np.zeros((_CHUNK, WIDTH)))
            self._row = 0
        row = self._chunks[-1][self._row]
        self._row += 1
        return row

    def __len__(self) -> int:
        return 0 if not self._chunks else (len(self._chunks) - 1) * _CHUNK + self._row

    def table(self) -> np.ndarray:
        """All rows so far, shape (ticks, WIDTH)."""
        if not self._chunks:
            return np.zeros((0, WIDTH))
        return np.concatenate([*self._chunks[:-1], self._chunks[-1][: self._row]])

    def arrays(self) -> dict[str, np.ndarray]:
        """The columns by name: ``t_s`` shape (ticks,), the others (ticks, 3)."""
        table = self.table()
        out = {}
        for name, (start, width) in COLUMNS.items():
            out[name] = table[:, start] if width == 1 else table[:, start : start + width]
        return out

    def save(self, path: str | Path) -> None:
        """Write the columns to an ``.npz`` file."""
        np.savez(Path(path), allow_pickle=True, **self.arrays())
