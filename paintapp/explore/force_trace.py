"""The force trace of a scripted exploration: per servo tick, the force written to the device
(scaled, filtered and clamped by the servo loop) beside the fluid's physical force and torque on
the probe in SI (N, N m; in 2D times the probe's depth), held from the latest evaluation.

CSV columns: :data:`~paintapp.haptics.force_csv.DEVICE_COLUMNS` (as a painting replay writes
them), then :data:`FLUID_COLUMNS`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from paintapp.atomic import atomic_path
from paintapp.haptics.force_csv import DEVICE_COLUMNS, read_trace_csv, write_trace_csv

#: The fluid's columns, beside the device's.
FLUID_COLUMNS = (
    "fluid_force_x_n",
    "fluid_force_y_n",
    "fluid_force_z_n",
    "fluid_torque_x_nm",
    "fluid_torque_y_nm",
    "fluid_torque_z_nm",
)
COLUMNS = (*DEVICE_COLUMNS, *FLUID_COLUMNS)


def fluid_at_ticks(trace: np.ndarray, evaluations: np.ndarray) -> np.ndarray:
    """The fluid's force and torque (ticks, 6) at each tick of ``trace`` (ticks, 7): the latest
    evaluation (n, 7: time, force xyz, torque xyz) at or before the tick (the first before it)."""
    if len(evaluations) == 0:
        return np.zeros((len(trace), 6))
    index = np.searchsorted(evaluations[:, 0], trace[:, 0] + 1e-12, side="right") - 1
    return evaluations[np.clip(index, 0, len(evaluations) - 1), 1:7]


def write_explore_forces_csv(path: str | Path, trace: np.ndarray, evaluations: np.ndarray) -> None:
    """Write the device's trace (ticks, 7) and the fluid's force beside it, atomically."""
    write_trace_csv(path, COLUMNS, np.column_stack([trace, fluid_at_ticks(trace, evaluations)]))


def read_explore_forces_csv(path: str | Path) -> tuple[np.ndarray, np.ndarray]:
    """The device's trace (ticks, 7) and the fluid's force and torque (ticks, 6) of a file
    :func:`write_explore_forces_csv` wrote; :class:`InputError` on a malformed file."""
    data = read_trace_csv(path, COLUMNS)
    return data[:, : len(DEVICE_COLUMNS)], data[:, len(DEVICE_COLUMNS) :]


def plot_explore_forces(
    path: str | Path, trace: np.ndarray, evaluations: np.ndarray, title: str
) -> None:
    """Plot the device's force, the fluid's force and the fluid's torque to a PNG."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    t = trace[:, 0]
    fluid = fluid_at_ticks(trace, evaluations)
    fig = Figure(figsize=(9, 8), constrained_layout=True)
    FigureCanvasAgg(fig)
    device, physical, torque = fig.subplots(3, 1, sharex=True)
    for i, name in enumerate("xyz"):
        device.plot(t, trace[:, 1 + i], lw=0.8, label=f"F{name}")
        physical.plot(t, fluid[:, i], lw=0.8, label=f"F{name}")
        torque.plot(t, fluid[:, 3 + i], lw=0.8, label=f"τ{name}")
    device.set_ylabel("written to the device (N)")
    physical.set_ylabel("fluid force on the probe (N)")
    torque.set_ylabel("fluid torque (N m)")
    torque.set_xlabel("time (s)")
    device.set_title(title)
    for ax in (device, physical, torque):
        ax.grid(alpha=0.3)
        ax.legend(loc="upper right", fontsize=8, ncol=3)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
