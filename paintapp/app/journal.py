"""The stroke journal: every sample and event the painting session consumed, as it happens.

The simulation worker writes each stylus sample it hands to the session, and every palette or
brush event, through a :class:`~paintapp.strokes.recorder.StrokeRecorder` (one flushed line per
record), so a crash loses at most the line being written. Times are the session's own clock, so
replaying the journal (``paintapp replay``) paints the same strokes in the same steps.

Actions the stroke format has no event for are written as ``marker`` events, which replay
ignores: ``undo``, ``redo``, ``fluid_model <name>``, ``viscosity_pa_s <v>``, ``brush_scale <s>``,
``device fault: ...``, ``slab put <pigment>``, ``slab clear``. A replay therefore repaints undone
strokes, with the header scene's settings. Paint picked up from the mixing slab is written as a
``slab dab`` or ``slab mix`` marker, a ``clean`` and one ``load_pigment`` per pigment the brush
then carries, so a replay loads the same mixture without replaying the slab.

When the canvas is replaced (new canvas, open, recovery) the journal moves on to a new file next
to the first one (``name-2.jsonl``, ``name-3.jsonl``, ...): a stroke file describes one canvas.
"""

from __future__ import annotations

import re
from pathlib import Path

from common.errors import InputError
from paintapp.canvas.model import Canvas
from paintapp.strokes.recorder import StrokeRecorder
from paintapp.strokes.records import Marker, StrokeHeader, StrokeRecord

_NAME = re.compile(r"[^A-Za-z0-9_.-]")


def scene_label(name: str) -> str | None:
    """A scene name as the header accepts it (None: the default scene)."""
    if name == "default":
        return None
    return _NAME.sub("_", name)[:64] or None


def make_header(
    canvas: Canvas, brush: str, pigments: tuple[str, ...], scene: str, device_kind: str
) -> StrokeHeader:
    """The header for a journal of painting on ``canvas``."""
    return StrokeHeader.from_dict(
        {
            "format": StrokeHeader.FORMAT,
            "version": StrokeHeader.VERSION,
            "canvas": {"pixels": list(canvas.pixels), "size_m": list(canvas.size_m)},
            "brush": brush,
            "pigments": list(pigments),
            "scene": scene_label(scene),
            "device": {"kind": device_kind, "name": "paintapp paint"},
            "seed": 0,
        }
    )


class Journal:
    """Writes the session's records to ``path`` (or nowhere when ``path`` is None).

    Args:
        path: the recording file; it must not exist yet unless ``overwrite``.
        overwrite: allow replacing an existing file.
    """

    def __init__(self, path: str | Path | None, overwrite: bool = False) -> None:
        self.first_path = Path(path) if path is not None else None
        self.overwrite = overwrite
        self.recorder: StrokeRecorder | None = None
        self.part = 0
        self.records = 0
        self.error: str | None = None

    @property
    def path(self) -> Path | None:
        """The file being written now."""
        return self.recorder.path if self.recorder is not None else None

    def _next_path(self) -> Path | None:
        if self.first_path is None:
            return None
        self.part += 1
        if self.part == 1:
            return self.first_path
        p = self.first_path
        return p.with_name(f"{p.stem}-{self.part}{p.suffix}")

    def start(self, header: StrokeHeader) -> None:
        """Begin a file for a (new) canvas; the previous one is closed."""
        self.close()
        path = self._next_path()
        if path is None:
            return
        self.recorder = StrokeRecorder(path, header, overwrite=self.overwrite or self.part > 1)

    def write(self, record: StrokeRecord) -> None:
        """Append one record. A write failure (disk full, ...) stops journalling with a note
        instead of stopping the painting."""
        if self.recorder is None:
            return
        try:
            self.recorder.write(record)
            self.records += 1
        except (OSError, InputError, ValueError) as exc:
            self.error = f"recording stopped: {exc}"
            self.close()

    def marker(self, t_s: float, label: str) -> None:
        """Append a ``marker`` event."""
        self.write(Marker(t_s, label[:200]))

    def close(self) -> None:
        """Flush and close the current file."""
        if self.recorder is not None:
            self.recorder.close()
            self.recorder = None
