"""Shared data and drawing for the square-sweep figures (paper Figs. 4 and 5)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from common.errors import InputError
from paintapp.bench.square_sweep import SweepTrace, run_sweep, sweep_scene, sweep_summary

MIN_CELLS = 8  # the 0.12 m square must span a few cells
MAX_CELLS = 512


@dataclass
class SweepFigureData:
    """One sweep ready to plot.

    Attributes:
        trace: the recorded forces and motion.
        drag: force along the motion, shape (n,), N/m (negative: it opposes the motion).
        perpendicular: force across the motion (90 degrees counter-clockwise), shape (n,), N/m.
        summary: noise and sign figures of :func:`~paintapp.bench.square_sweep.sweep_summary`.
        boundary_method: the solver's ``boundary_method`` (``staircase`` or ``cutcell``).
    """

    trace: SweepTrace
    drag: np.ndarray
    perpendicular: np.ndarray
    summary: dict[str, float]
    boundary_method: str = "staircase"

    @property
    def cells(self) -> int:
        return int(self.trace.cells[0])


def check_cells(cells: int) -> int:
    """Validate a grid size for the sweep figures."""
    if isinstance(cells, bool) or not isinstance(cells, int) or not MIN_CELLS <= cells <= MAX_CELLS:
        raise InputError(
            f"expected a grid of {MIN_CELLS} to {MAX_CELLS} cells per side, got {cells!r}",
            key="--cells",
        )
    return cells


def sweep_data(
    cells: int = 64, force_model: str = "stress", boundary_method: str = "staircase"
) -> SweepFigureData:
    """Run the paper's sweep at ``cells`` per side with ``force_model`` and ``boundary_method``."""
    solver = {"force_model": force_model, "boundary_method": boundary_method}
    trace = run_sweep(sweep_scene(check_cells(cells), solver=solver))
    drag, perp = trace.components()
    return SweepFigureData(trace, drag, perp, sweep_summary(trace), boundary_method)


def save_figure(fig, path: str | Path) -> None:
    """Write a matplotlib figure as PNG atomically and close it."""
    import matplotlib.pyplot as plt

    from paintapp.atomic import atomic_write_with

    atomic_write_with(path, lambda tmp: fig.savefig(tmp, dpi=110, format="png"))
    plt.close(fig)


def pyplot():
    """matplotlib.pyplot on the Agg backend (no display needed)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def mark_phases(ax) -> None:
    """Shade the two moving phases (0-1 s out, 1-2 s back) of the sweep."""
    ax.axvspan(0.0, 1.0, color="0.93", zorder=0)
    ax.axvspan(1.0, 2.0, color="0.97", zorder=0)
    ax.axhline(0.0, color="0.5", lw=0.6)
