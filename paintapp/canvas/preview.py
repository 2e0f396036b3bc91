"""PNG previews: linear scene-referred RGB to 8-bit sRGB images, written atomically."""

from __future__ import annotations

import functools
import math
from pathlib import Path

import numpy as np
import OpenImageIO as oiio

from paintapp.atomic import atomic_path
from paintapp.canvas.srgb8_rows import srgb8_rows
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
    picture = np.ascontiguousarray(rgba, np.float32)
    if picture.ndim != 3 or picture.shape[2] not in (3, 4):
        raise ValueError(f"expected a picture (H, W, 3|4), got shape {picture.shape}")
    out = np.empty((*picture.shape[:2], 3), np.uint8)
    scale = np.float32(2.0**exposure_stops)
    srgb8_rows(picture, scale, _srgb8_tables(), BUCKET_SHIFT, out)  # as srgb8, in one pass
    return out


#: A float32's bits shifted right by this many select its bucket in :func:`_srgb8_tables`.
BUCKET_SHIFT = 12
_ONE_BITS = int(np.float32(1.0).view(np.int32))


def srgb8_reference(linear: np.ndarray) -> np.ndarray:
    """8-bit sRGB codes of float32 linear values: NaN as 0, clipped to [0, 1], encoded
    (:func:`paintapp.pigments.spectra.srgb_encode`, in float64), times 255, rounded half to even.
    The definition :func:`srgb8` computes faster."""
    encoded = srgb_encode(np.nan_to_num(np.asarray(linear, np.float32), nan=0.0))
    return np.round(encoded * 255.0).astype(np.uint8)


def srgb8(linear: np.ndarray) -> np.ndarray:
    """:func:`srgb8_reference`, the same codes (every float32 checked), from tables over the
    values' bits: the float32 values in [0, 1] ordered as their bits, cut into buckets of
    ``2 ** BUCKET_SHIFT`` values, each holding at most one of the 255 values where the code
    steps up; a value's code is its bucket's first code, plus one past that bucket's step."""
    first, step_bits = _srgb8_tables()
    x = np.asarray(linear, np.float32)
    bits = np.where(np.isnan(x), np.int32(0), x.view(np.int32))
    np.clip(bits, 0, _ONE_BITS, out=bits)  # negatives (and -0) to 0, past 1 (and inf) to 1
    bucket = bits >> BUCKET_SHIFT
    return first[bucket] + (bits >= step_bits[bucket]).astype(np.uint8)


@functools.lru_cache(maxsize=1)
def _srgb8_tables() -> tuple[np.ndarray, np.ndarray]:
    """(first code of each bucket, uint8; the bits of the value in it where the code steps up,
    int32, or past every value's where none does): the steps found by bisection over the float32
    bits on :func:`srgb8_reference` itself."""
    k = np.arange(1, 256)
    lo = np.zeros(255, np.int64)
    hi = np.full(255, _ONE_BITS, np.int64)
    while np.any(lo < hi):
        mid = (lo + hi) // 2
        up = srgb8_reference(mid.astype(np.int32).view(np.float32)).astype(np.int64) >= k
        hi, lo = np.where(up, mid, hi), np.where(up, lo, mid + 1)
    steps = hi.astype(np.int32)
    buckets = (_ONE_BITS >> BUCKET_SHIFT) + 1
    starts = (np.arange(buckets, dtype=np.int64) << BUCKET_SHIFT).astype(np.int32)
    first = np.searchsorted(steps, starts, side="right").astype(np.uint8)
    step_bits = np.full(buckets, np.iinfo(np.int32).max, np.int32)
    step_bits[steps >> BUCKET_SHIFT] = steps
    if len(np.unique(steps >> BUCKET_SHIFT)) != len(steps):
        raise AssertionError("two sRGB code steps in one bucket")
    return first, step_bits


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
