"""Which texels of the canvas are in sight, and what is left to shade outside it.

The renderer's cached picture (:meth:`CanvasRenderer.render_cached`) is shaded only where it is
stale and in sight; the stale parts out of sight wait, as a short list of texel boxes, until a
view shows them.
"""

from __future__ import annotations

import math

from paintapp.canvas.regions import Box, clip_box, union_box

#: Stale boxes kept apart before they are merged into one (bounds the bookkeeping).
MAX_STALE_BOXES = 32


def texel_box_in_sight(
    box_m: tuple[float, float, float, float],
    texel_m: tuple[float, float],
    pixels: tuple[int, int],
    grow: int = 1,
) -> Box | None:
    """The texture texels (x0, y0, x1, y1) under canvas rectangle ``box_m`` (metres), grown by
    ``grow`` texels each way (what bilinear filtering and the lighting's slopes reach) and
    clipped to a texture of ``pixels`` (W, H); None when nothing of it is on the texture."""
    x0, y0, x1, y1 = box_m
    dx, dy = texel_m
    values = (x0 / dx, y0 / dy, x1 / dx, y1 / dy)
    if not all(math.isfinite(v) for v in values):
        return (0, 0, *pixels)
    w, h = pixels
    box = (
        _within(math.floor(values[0]) - grow, w),
        _within(math.floor(values[1]) - grow, h),
        _within(math.ceil(values[2]) + grow, w),
        _within(math.ceil(values[3]) + grow, h),
    )
    return clip_box(box, pixels)


def _within(v: int, n: int) -> int:
    """``v`` held to [0, n]."""
    return min(max(v, 0), n)


def intersect(a: Box, b: Box) -> Box | None:
    """The overlap of two boxes, or None."""
    x0, y0 = max(a[0], b[0]), max(a[1], b[1])
    x1, y1 = min(a[2], b[2]), min(a[3], b[3])
    if x1 <= x0 or y1 <= y0:
        return None
    return x0, y0, x1, y1


def outside(box: Box, sight: Box) -> list[Box]:
    """The parts of ``box`` outside ``sight`` (at most four boxes, none overlapping)."""
    inner = intersect(box, sight)
    if inner is None:
        return [box]
    x0, y0, x1, y1 = box
    ix0, iy0, ix1, iy1 = inner
    parts = [
        (x0, y0, x1, iy0),  # below
        (x0, iy1, x1, y1),  # above
        (x0, iy0, ix0, iy1),  # left
        (ix1, iy0, x1, iy1),  # right
    ]
    return [p for p in parts if p[2] > p[0] and p[3] > p[1]]


def split_stale(stale: list[Box], sight: Box | None) -> tuple[list[Box], list[Box]]:
    """What to shade now of the stale boxes ``stale`` (their parts in ``sight``, merged into
    one box when there are more than a few), and the stale boxes left (their parts out of
    sight). A ``sight`` of None means everything is in sight: one box bounding them all."""
    if sight is None:
        whole = _bounding(stale)
        return ([] if whole is None else [whole]), []
    shade: list[Box] = []
    rest: list[Box] = []
    for box in stale:
        inner = intersect(box, sight)
        if inner is not None:
            shade.append(inner)
        rest += outside(box, sight)
    if len(shade) > 4:
        shade = [_bounding(shade)]  # type: ignore[list-item]
    if len(rest) > MAX_STALE_BOXES:
        rest = [_bounding(rest)]  # type: ignore[list-item]
    return shade, rest


def _bounding(boxes: list[Box]) -> Box | None:
    """The box bounding ``boxes`` (None for none)."""
    whole: Box | None = None
    for box in boxes:
        whole = union_box(whole, box)
    return whole
