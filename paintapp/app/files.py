"""Canvas files from the window: new, open, save, save as, export. All writes are atomic (the
canvas and preview writers write a temporary file and rename it).

Saving takes a copy of the display canvas (holding the shared lock only for the copy) and the lit
picture from the window's renderer, then writes outside the lock, so painting goes on meanwhile.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from PySide6.QtWidgets import QFileDialog, QMessageBox

from paintapp.app import actions
from paintapp.app.options import blank_canvas
from paintapp.canvas_io import read_canvas_exr, unlit_rgba, write_canvas_exr
from paintapp.canvas_preview import write_preview_png
from solver.errors import InputError

if TYPE_CHECKING:
    from paintapp.app.window import PaintWindow

EXR_FILTER = "OpenEXR canvas (*.exr)"
EXPORT_FILTER = "PNG picture (*.png);;OpenEXR canvas (*.exr)"


def _warn(window: PaintWindow, title: str, exc: Exception) -> None:
    if window.interactive:
        QMessageBox.warning(window, title, str(exc))
    window.statusBar().showMessage(f"{title}: {exc}", 10000)


def new_canvas(window: PaintWindow) -> None:
    """Start a blank canvas of the same size (the undo history restarts)."""
    canvas = blank_canvas(window.shared.canvas)
    window.worker.submit(actions.replace_canvas(canvas, "new canvas"))
    window.set_document(None)


def open_canvas(window: PaintWindow, path: str | Path | None = None) -> bool:
    """Open a canvas EXR (asks for the file when ``path`` is None); True when opened."""
    if path is None:
        path, _ = QFileDialog.getOpenFileName(window, "Open canvas", "", EXR_FILTER)
        if not path:
            return False
    try:
        canvas = read_canvas_exr(path)
        window.library.require(canvas.pigment_names, source=str(path))
    except InputError as exc:
        _warn(window, "Cannot open the canvas", exc)
        return False
    window.worker.submit(actions.replace_canvas(canvas, f"opened {path}"))
    window.set_document(Path(path))
    return True


def save_canvas(window: PaintWindow, path: str | Path | None = None, ask: bool = False) -> bool:
    """Save the canvas EXR to ``path``, the current document, or a file asked for."""
    target = Path(path) if path is not None else window.document
    if target is None or ask:
        chosen, _ = QFileDialog.getSaveFileName(window, "Save canvas", "", EXR_FILTER)
        if not chosen:
            return False
        target = Path(chosen)
    if target.suffix.lower() != ".exr":
        target = target.with_suffix(".exr")
    try:
        canvas, version = window.shared.snapshot()
        write_canvas_exr(target, canvas, window.picture_for(canvas), library=window.library)
        window.saved_version = version
    except (OSError, InputError, ValueError, RuntimeError) as exc:
        _warn(window, "Cannot save the canvas", exc)
        return False
    window.set_document(target)
    window.statusBar().showMessage(f"saved {target}", 5000)
    return True


def export_picture(window: PaintWindow, path: str | Path | None = None) -> bool:
    """Export the lit picture: a PNG preview, or a full canvas EXR."""
    if path is None:
        chosen, _ = QFileDialog.getSaveFileName(window, "Export", "", EXPORT_FILTER)
        if not chosen:
            return False
        path = chosen
    target = Path(path)
    try:
        canvas, _ = window.shared.snapshot()
        rgba = window.picture_for(canvas)
        if target.suffix.lower() == ".exr":
            write_canvas_exr(target, canvas, rgba, library=window.library)
        else:
            if rgba is None:
                rgba = unlit_rgba(canvas, window.library)
            write_preview_png(target.with_suffix(".png"), rgba)
    except (OSError, InputError, ValueError, RuntimeError) as exc:
        _warn(window, "Cannot export", exc)
        return False
    window.statusBar().showMessage(f"exported {target}", 5000)
    return True
