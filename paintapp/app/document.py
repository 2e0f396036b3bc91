"""The window's document: which file the canvas belongs to, and new, open, save, save as, export.

A :class:`Document` knows the shared display canvas, the pigments, how to hand work to the
simulation worker and how to get the lit picture; it asks the user and reports through a small
:class:`FileDialogs` interface that the window implements, so this module needs no window.

All writes are atomic (the canvas and preview writers write a temporary file and rename it).
Saving takes a copy of the display canvas (holding the shared lock only for the copy) and the lit
picture from the renderer, then writes outside the lock, so painting goes on meanwhile.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Protocol

import numpy as np

from common.errors import InputError
from paintapp.app import actions
from paintapp.app.options import blank_canvas
from paintapp.app.shared import SharedCanvas
from paintapp.canvas.exr import read_canvas_exr, unlit_rgba, write_canvas_exr
from paintapp.canvas.model import Canvas
from paintapp.canvas.preview import write_preview_png
from paintapp.pigments.library import PigmentLibrary

if TYPE_CHECKING:
    from paintapp.app.worker import Command

EXR_FILTER = "OpenEXR canvas (*.exr)"
EXPORT_FILTER = "PNG picture (*.png);;OpenEXR canvas (*.exr)"


class FileDialogs(Protocol):
    """How a document asks for file names and tells the user what happened."""

    def ask_open(self, title: str, filter_text: str) -> str | None: ...

    def ask_save(self, title: str, filter_text: str) -> str | None: ...

    def warn(self, title: str, exc: Exception) -> None: ...

    def status(self, message: str) -> None: ...

    def titled(self, path: Path | None) -> None: ...


@dataclass
class Document:
    """The canvas file being edited.

    Attributes:
        shared: the display canvas (snapshots are taken from it).
        library: the pigments (a canvas that names other pigments is refused).
        submit: hands an action to the simulation worker.
        picture_for: the lit picture of a canvas snapshot, or None (then the unlit colour is used).
        dialogs: the user interface's file dialogs and messages.
        path: the file the canvas is saved to (None: untitled).
        saved_version: the display canvas version last saved.
        on_surface: told the surface of each canvas made or opened (the haptic contact follows
            its tooth); None: nobody listens.
    """

    shared: SharedCanvas
    library: PigmentLibrary
    submit: Callable[[Command], None]
    picture_for: Callable[[Canvas], np.ndarray | None]
    dialogs: FileDialogs
    path: Path | None = None
    saved_version: int = field(default=0)
    on_surface: Callable[[str], None] | None = None

    def set_path(self, path: Path | None) -> None:
        """The file the canvas is saved to."""
        self.path = path
        self.dialogs.titled(path)

    @property
    def unsaved(self) -> bool:
        """True when the display canvas changed since the last save."""
        return self.shared.version != self.saved_version

    def new(
        self,
        pixels: tuple[int, int] | None = None,
        size_m: tuple[float, float] | None = None,
        surface: str | None = None,
    ) -> None:
        """Start a blank canvas (the undo history restarts): ``pixels`` texels over ``size_m``
        metres on ``surface`` (:mod:`paintapp.canvas.surfaces`), each the current canvas's
        where not given. InputError for a bad size or an unknown surface."""
        like = self.shared.canvas
        if pixels is None and size_m is None and surface is None:
            canvas = blank_canvas(like)
        else:
            canvas = Canvas(
                pixels if pixels is not None else like.pixels,
                size_m if size_m is not None else like.size_m,
                surface=surface if surface is not None else like.surface,
            )
        self.submit(actions.replace_canvas(canvas, f"new canvas ({canvas.surface})"))
        self.set_path(None)
        self._surface(canvas.surface)

    def _surface(self, surface: str) -> None:
        if self.on_surface is not None:
            self.on_surface(surface)

    def open(self, path: str | Path | None = None) -> bool:
        """Open a canvas EXR (asks for the file when ``path`` is None); True when opened."""
        if path is None:
            path = self.dialogs.ask_open("Open canvas", EXR_FILTER)
            if not path:
                return False
        try:
            canvas = read_canvas_exr(path)
            self.library.require(canvas.pigment_names, source=str(path))
        except InputError as exc:
            self.dialogs.warn("Cannot open the canvas", exc)
            return False
        self.submit(actions.replace_canvas(canvas, f"opened {path}"))
        self.set_path(Path(path))
        self._surface(canvas.surface)
        return True

    def save(self, path: str | Path | None = None, ask: bool = False) -> bool:
        """Save the canvas EXR to ``path``, the current file, or a file asked for."""
        target = Path(path) if path is not None else self.path
        if target is None or ask:
            chosen = self.dialogs.ask_save("Save canvas", EXR_FILTER)
            if not chosen:
                return False
            target = Path(chosen)
        if target.suffix.lower() != ".exr":
            target = target.with_suffix(".exr")
        try:
            canvas, version = self.shared.snapshot()
            write_canvas_exr(target, canvas, self.picture_for(canvas), library=self.library)
            self.saved_version = version
        except (OSError, InputError, ValueError, RuntimeError) as exc:
            self.dialogs.warn("Cannot save the canvas", exc)
            return False
        self.set_path(target)
        self.dialogs.status(f"saved {target}")
        return True

    def export(self, path: str | Path | None = None) -> bool:
        """Export the lit picture: a PNG preview, or a full canvas EXR."""
        if path is None:
            path = self.dialogs.ask_save("Export", EXPORT_FILTER)
            if not path:
                return False
        target = Path(path)
        try:
            canvas, _ = self.shared.snapshot()
            rgba = self.picture_for(canvas)
            if target.suffix.lower() == ".exr":
                write_canvas_exr(target, canvas, rgba, library=self.library)
            else:
                if rgba is None:
                    rgba = unlit_rgba(canvas, self.library)
                write_preview_png(target.with_suffix(".png"), rgba)
        except (OSError, InputError, ValueError, RuntimeError) as exc:
            self.dialogs.warn("Cannot export", exc)
            return False
        self.dialogs.status(f"exported {target}")
        return True
