"""Files a replay writes: the canvas EXR and PNG preview, the force trace as CSV, and its plot.

Forces CSV: a header row naming the columns (:data:`paintapp.session.playback.FORCE_COLUMNS`: time in s,
then force x, y, z in N and torque x, y, z in N m, canvas frame), then one row per servo tick.
"""

from __future__ import annotations

import sys
from concurrent.futures import ThreadPoolExecutor, wait
from pathlib import Path

import numpy as np

from paintapp.atomic import atomic_path
from paintapp.canvas.exr import unlit_rgba, write_canvas_exr
from paintapp.canvas.model import Canvas
from paintapp.canvas.preview import write_preview_png
from paintapp.haptics.force_csv import read_trace_csv, write_trace_csv
from paintapp.pigments.library import PigmentLibrary, load_pigment_library
from paintapp.session.playback import FORCE_COLUMNS


def write_forces_csv(path: str | Path, forces: np.ndarray) -> None:
    """Write a force trace (ticks, 7) as CSV (header row, one row per tick), atomically."""
    write_trace_csv(path, FORCE_COLUMNS, forces)


def read_forces_csv(path: str | Path) -> np.ndarray:
    """Read a forces CSV back as (ticks, 7); :class:`InputError` on a malformed file."""
    return read_trace_csv(path, FORCE_COLUMNS)


def canvas_picture(
    canvas: Canvas, library: PigmentLibrary | None = None, *, lit: bool = True
) -> np.ndarray:
    """Linear RGBA (H, W, 4) of the canvas: the lit GPU render, or the unlit CPU colour when
    ``lit`` is False or no OpenGL context can be made (a note goes to stderr then)."""
    library = library or load_pigment_library()
    if lit:
        from paintapp.render import RenderUnavailable, render_canvas_rgba

        try:
            return render_canvas_rgba(canvas, library)
        except RenderUnavailable as exc:
            print(f"note: {exc}; writing the unlit colour instead", file=sys.stderr)
    return unlit_rgba(canvas, library)


def write_canvas_outputs(
    canvas: Canvas,
    exr: str | Path | None,
    preview: str | Path | None = None,
    *,
    lit: bool = True,
    half: bool = True,
    picture: np.ndarray | None = None,
) -> None:
    """Write the canvas EXR and/or a PNG preview (one picture for both, ``picture`` where given,
    else :func:`canvas_picture`'s; the preview is encoded on a thread of its own while the EXR is
    written: both compress with the interpreter lock released)."""
    if exr is None and preview is None:
        return
    rgba = canvas_picture(canvas, lit=lit) if picture is None else picture
    with ThreadPoolExecutor(max_workers=1, thread_name_prefix="preview") as pool:
        png = pool.submit(write_preview_png, preview, rgba) if preview is not None else None
        try:
            if exr is not None:
                write_canvas_exr(exr, canvas, rgba, half=half)
        finally:
            if png is not None:
                wait([png])  # an error in the EXR's writing goes first
        if png is not None:
            png.result()


def plot_forces(path: str | Path, forces: np.ndarray, title: str = "force on the brush") -> None:
    """Plot a force trace (force components and magnitude; torque components) to a PNG.

    Drawn on a figure of its own with the Agg canvas, without pyplot (no global figure state,
    no backend chosen for the process, and 0.05-0.1 s less to import)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    forces = np.asarray(forces, dtype=float).reshape(-1, len(FORCE_COLUMNS))
    t = forces[:, 0]
    fig = Figure(figsize=(9, 6), constrained_layout=True)
    FigureCanvasAgg(fig)
    top, bottom = fig.subplots(2, 1, sharex=True)
    for i, name in enumerate("xyz"):
        top.plot(t, forces[:, 1 + i], lw=0.8, label=f"F{name}")
        bottom.plot(t, 1e3 * forces[:, 4 + i], lw=0.8, label=f"τ{name}")
    top.plot(t, np.linalg.norm(forces[:, 1:4], axis=1), "k", lw=1.0, label="|F|")
    top.set_ylabel("force written to the device (N)")
    bottom.set_ylabel("torque (mN m)")
    bottom.set_xlabel("time (s)")
    top.set_title(title)
    for ax in (top, bottom):
        ax.grid(alpha=0.3)
        ax.legend(loc="upper right", fontsize=8, ncol=4)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
