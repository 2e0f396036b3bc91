"""Undo and redo per stroke, storing only the region each stroke changed.

The history keeps a *base* copy of the canvas: the canvas as it was after the last recorded edit.
When a stroke ends, :meth:`UndoHistory.commit` compares the live canvas with the base inside the
region the stroke touched (the union of the dirty boxes it produced), trims that to the texels
whose paint actually changed, and stores the before (from the base) and after (from the live
canvas) blocks of paint and wetness. Undo writes the before block back, redo the after block.

Drying changes wetness everywhere between strokes without being an edit; the base's wetness
lags behind it, so an undo restores the wetness a region had when it was last painted (the paint
comes back as wet as it was then). Pigments only ever get appended to a canvas, so an old edit
whose block has fewer pigment channels is padded with zeros for the newer ones.

Memory is bounded twice: at most ``max_steps`` edits, and at most ``max_bytes`` for all stored
blocks together; the oldest edits are dropped first (the newest one is always kept).
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import numpy as np

from paintapp.canvas.model import Canvas
from paintapp.canvas.regions import Box, box_of_nonzero, union_box

#: Default limits: steps and bytes.
DEFAULT_MAX_STEPS = 100
DEFAULT_MAX_BYTES = 256 * 1024 * 1024


@dataclass(frozen=True)
class RegionEdit:
    """One undoable edit: a block of the canvas before and after.

    Attributes:
        box: (x0, y0, x1, y1) texels.
        pigments: the canvas's pigment names when the edit was made (channel order of the blocks).
        before_paint, after_paint: (P, h, w) float32 paint thickness, m.
        before_wet, after_wet: (h, w) float32 wetness.
        label: what the edit was ("stroke").
    """

    box: Box
    pigments: tuple[str, ...]
    before_paint: np.ndarray
    before_wet: np.ndarray
    after_paint: np.ndarray
    after_wet: np.ndarray
    label: str = "stroke"

    @property
    def nbytes(self) -> int:
        """Bytes held by the blocks."""
        blocks = (self.before_paint, self.before_wet, self.after_paint, self.after_wet)
        return sum(b.nbytes for b in blocks)


def copy_canvas(canvas: Canvas) -> Canvas:
    """A deep copy of ``canvas`` (paint, wetness, pigments, surface), with nothing marked dirty."""
    return Canvas(
        canvas.pixels,
        canvas.size_m,
        canvas.pigment_names,
        canvas.paint_m.copy(),
        canvas.wetness.copy(),
        canvas.surface,
    )


def match_pigments(dst: Canvas, names: tuple[str, ...]) -> None:
    """Append to ``dst`` any pigment of ``names`` it lacks (in order)."""
    for name in names:
        if name not in dst.pigment_names:
            dst.add_pigment(name)


def copy_region(src: Canvas, dst: Canvas, box: Box) -> None:
    """Copy paint and wetness in ``box`` from ``src`` to ``dst`` (same size; pigments matched)."""
    match_pigments(dst, src.pigment_names)
    x0, y0, x1, y1 = box
    for i, name in enumerate(src.pigment_names):
        dst.paint_m[dst.pigment_index(name), y0:y1, x0:x1] = src.paint_m[i, y0:y1, x0:x1]
    dst.wetness[y0:y1, x0:x1] = src.wetness[y0:y1, x0:x1]


def _block_for(canvas: Canvas, edit_pigments: tuple[str, ...], paint: np.ndarray) -> np.ndarray:
    """The edit's paint block laid out in the canvas's current channel order."""
    out = np.zeros((len(canvas.pigment_names), *paint.shape[1:]), np.float32)
    for i, name in enumerate(edit_pigments):
        out[canvas.pigment_index(name)] = paint[i]
    return out


class UndoHistory:
    """Per-stroke undo/redo over one canvas (see the module docstring).

    Args:
        canvas: the live canvas (the history copies it as its base).
        max_steps: most edits kept (at least 1).
        max_bytes: most bytes kept over all edits.
    """

    def __init__(
        self,
        canvas: Canvas,
        max_steps: int = DEFAULT_MAX_STEPS,
        max_bytes: int = DEFAULT_MAX_BYTES,
    ) -> None:
        self.max_steps = max(1, int(max_steps))
        self.max_bytes = int(max_bytes)
        self.base = copy_canvas(canvas)
        self._undo: deque[RegionEdit] = deque()
        self._redo: list[RegionEdit] = []

    @property
    def undo_count(self) -> int:
        """Edits that can be undone."""
        return len(self._undo)

    @property
    def redo_count(self) -> int:
        """Edits that can be redone."""
        return len(self._redo)

    @property
    def nbytes(self) -> int:
        """Bytes held by all stored edits."""
        return sum(e.nbytes for e in (*self._undo, *self._redo))

    def commit(self, canvas: Canvas, region: Box | None, label: str = "stroke") -> Box | None:
        """Record the change of ``canvas`` inside ``region`` since the last edit.

        Returns the box stored, or None when the paint did not change there.
        """
        if region is None:
            return None
        match_pigments(self.base, canvas.pigment_names)
        x0, y0, x1, y1 = region
        live = canvas.paint_m[:, y0:y1, x0:x1]
        base = _block_for(canvas, self.base.pigment_names, self.base.paint_m[:, y0:y1, x0:x1])
        changed = box_of_nonzero(np.any(live != base, axis=0))
        if changed is None:
            return None
        bx0, by0, bx1, by1 = changed
        box = (x0 + bx0, y0 + by0, x0 + bx1, y0 + by1)
        edit = self._edit(canvas, box, label)
        copy_region(canvas, self.base, box)
        self._undo.append(edit)
        self._redo.clear()
        self._trim()
        return box

    def _edit(self, canvas: Canvas, box: Box, label: str) -> RegionEdit:
        x0, y0, x1, y1 = box
        names = canvas.pigment_names
        before = _block_for(canvas, self.base.pigment_names, self.base.paint_m[:, y0:y1, x0:x1])
        return RegionEdit(
            box,
            names,
            before,
            self.base.wetness[y0:y1, x0:x1].copy(),
            canvas.paint_m[:, y0:y1, x0:x1].copy(),
            canvas.wetness[y0:y1, x0:x1].copy(),
            label,
        )

    def _trim(self) -> None:
        while len(self._undo) > self.max_steps:
            self._undo.popleft()
        while len(self._undo) > 1 and self.nbytes > self.max_bytes:
            self._undo.popleft()

    def _apply(self, canvas: Canvas, edit: RegionEdit, paint: np.ndarray, wet: np.ndarray) -> Box:
        match_pigments(canvas, edit.pigments)
        x0, y0, _, _ = edit.box
        canvas.write_region(x0, y0, _block_for(canvas, edit.pigments, paint), wet)
        copy_region(canvas, self.base, edit.box)
        return edit.box

    def undo(self, canvas: Canvas) -> Box | None:
        """Put back the paint from before the latest edit; returns its box (None: nothing)."""
        if not self._undo:
            return None
        edit = self._undo.pop()
        self._redo.append(edit)
        return self._apply(canvas, edit, edit.before_paint, edit.before_wet)

    def redo(self, canvas: Canvas) -> Box | None:
        """Re-apply the latest undone edit; returns its box (None: nothing)."""
        if not self._redo:
            return None
        edit = self._redo.pop()
        self._undo.append(edit)
        return self._apply(canvas, edit, edit.after_paint, edit.after_wet)


def grow(box: Box | None, other: Box | None) -> Box | None:
    """Union of two optional boxes (a stroke's region grows by each dirty box)."""
    return union_box(box, other)
