"""PNG previews: linear scene-referred RGB to 8-bit sRGB images, written atomically."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import OpenImageIO as oiio

from paintapp.atomic import atomic_path
from paintapp.pigments.spectra import srgb_encode

#: The exposures a preview accepts, stops (beyond them every pixel is black or white).
EXPOSURE_RANGE_STOPS = (-20.0, 20.0)


def encode_preview(rgba: np.ndarray, exposure_stops: float = 0.0) -> np.ndarray:
    """8-bit sRGB pixels (H, W, 3), top row first, from linear RGB(A) (H, W, 3|4), row 0 = bottom.

    Colours are scaled by ``2 ** exposure_stops``, clipped to [0, 1] and sRGB-encoded;
    ``exposure_stops`` must be finite and within :data:`EXPOSURE_RANGE_STOPS` (ValueError).
    """
    lo, hi = EXPOSURE_RANGE_STOPS
    if not (math.isfinite(exposure_stops) and lo <= exposure_stops <= hi):
        raise ValueError(f"expected an exposure in [{lo:g}, {hi:g}] stops, got {exposure_stops}")
    linear = np.asarray(rgba, np.float32)[::-1, :, :3] * np.float32(2.0**exposure_stops)
    encoded = srgb_encode(np.nan_to_num(linear, nan=0.0))
    return np.round(encoded * 255.0).astype(np.uint8)


def write_preview_png(path: str | Path, rgba: np.ndarray, exposure_stops: float = 0.0) -> None:
    """Write an sRGB 8-bit PNG preview of a linear picture (H, W, 3|4), row 0 = bottom."""
    pixels = encode_preview(rgba, exposure_stops)
    h, w = pixels.shape[:2]
    spec = oiio.ImageSpec(w, h, 3, "uint8")
    spec.attribute("oiio:ColorSpace", "sRGB")
    with atomic_path(path) as tmp:
        out = oiio.ImageOutput.create(str(tmp))
        if out is None:
            raise OSError(f"cannot create a PNG writer: {oiio.geterror()}")
        try:
            if not out.open(str(tmp), spec) or not out.write_image(pixels):
                raise OSError(f"cannot write {path}: {out.geterror()}")
        finally:
            out.close()
