"""Canvas sizes by name or in millimetres, at a texel size: what a new canvas is made of.

A size is a paper name (``a4``, ``a5``, ``a6``; portrait, ``-landscape`` turns it) or
``WxH`` in millimetres (``300x200``); with a texel size in millimetres (default 0.1 mm, finer
than a brush's bristle clumps) it gives the canvas's pixels and metres. The paint grid does not
depend on it: its cells are a whole number of texels chosen from the brush
(:func:`paintapp.paint.columns.cell_texels`), so a finer canvas only has more texels per cell.
"""

from __future__ import annotations

import math
import re

from common.errors import InputError
from paintapp.canvas.model import MAX_PIXELS

#: Paper sizes (portrait), millimetres.
PAPER_MM: dict[str, tuple[float, float]] = {
    "a4": (210.0, 297.0),
    "a5": (148.0, 210.0),
    "a6": (105.0, 148.0),
}
#: The canvas a new painting starts on: A4 portrait at 0.1 mm texels (2100 x 2970).
DEFAULT_SIZE = "a4"
DEFAULT_TEXEL_MM = 0.1
_MM = re.compile(r"^\s*([0-9]+(?:\.[0-9]*)?)\s*[xX]\s*([0-9]+(?:\.[0-9]*)?)\s*(?:mm)?\s*$")


def size_mm(text: str, key: str = "--canvas-size") -> tuple[float, float]:
    """(width, height) mm of a size name or ``WxH`` millimetres; InputError naming ``key``."""
    name = text.strip().lower()
    landscape = name.endswith("-landscape")
    base = name.removesuffix("-landscape")
    if base in PAPER_MM:
        w, h = PAPER_MM[base]
        return (h, w) if landscape else (w, h)
    match = _MM.match(name)
    if match is None:
        names = ", ".join(PAPER_MM)
        raise InputError(
            f"expected a paper size ({names}, optionally -landscape) or WxH in millimetres "
            f"(e.g. 300x200), got {text!r}",
            key=key,
        )
    w, h = float(match.group(1)), float(match.group(2))
    if not (w > 0.0 and h > 0.0 and w <= 10_000.0 and h <= 10_000.0):
        raise InputError(f"expected sides in (0, 10000] mm, got {text!r}", key=key)
    return w, h


def canvas_size(
    text: str = DEFAULT_SIZE, texel_mm: float = DEFAULT_TEXEL_MM
) -> tuple[tuple[int, int], tuple[float, float]]:
    """Pixels (W, H) and metres (w, h) of a canvas of size ``text`` at ``texel_mm`` texels.

    The pixel counts are the sides over the texel size, rounded; the metres are those pixels
    times the texel, so texels stay exactly square. InputError (naming ``--canvas-size`` or
    ``--texel-mm``) when the texel is not a finite size in [0.01, 5] mm or the canvas would
    exceed :data:`paintapp.canvas.model.MAX_PIXELS` texels a side."""
    if not (math.isfinite(texel_mm) and 0.01 <= texel_mm <= 5.0):
        raise InputError(
            f"expected a texel size in [0.01, 5] mm, got {texel_mm!r}", key="--texel-mm"
        )
    w_mm, h_mm = size_mm(text)
    pixels = (max(1, round(w_mm / texel_mm)), max(1, round(h_mm / texel_mm)))
    if max(pixels) > MAX_PIXELS:
        coarsest = max(w_mm, h_mm) / MAX_PIXELS
        raise InputError(
            f"{text} at {texel_mm:g} mm texels is {pixels[0]} x {pixels[1]} texels; at most "
            f"{MAX_PIXELS} a side (use --texel-mm {math.ceil(coarsest * 1000) / 1000:g} or more)",
            key="--texel-mm",
        )
    texel_m = texel_mm * 1e-3
    return pixels, (pixels[0] * texel_m, pixels[1] * texel_m)
