"""Canvas surfaces: the tooth of a ground (gesso, linen, cotton duck, paper) as a height field.

A surface is a periodic tile of heights, generated procedurally and deterministically from its
name (a fixed seed), and laid over the canvas at its real scale in millimetres: the tile repeats
every ``tile_mm`` along x and y, seamlessly (the weave's repeat and the noise's wavenumbers fit the
tile a whole number of times). Heights are metres along +z (out of the canvas), zero-mean, with a
stated peak-to-valley ``relief_um``. ``smooth`` is the flat plane of a canvas without tooth.

The bundled surfaces (:data:`SURFACES`):

=================  ==========================================================  ==========  ======
name               what                                                        relief      tile
=================  ==========================================================  ==========  ======
``smooth``         no tooth: the flat plane                                    0           -
``gesso``          sanded acrylic gesso: faint noise, wavelengths 0.15-2 mm     8 um        16 mm
``fine_linen``     plain-weave linen, thread pitch 0.35 mm, uneven threads     40 um       14 mm
``cotton_duck``    plain-weave cotton duck, thread pitch 1.0 mm                120 um      24 mm
``cold_press``     cold-pressed watercolour paper: rounded bumps, 0.3-3 mm     70 um       20 mm
=================  ==========================================================  ==========  ======

A woven surface is a plain weave: warp threads along y and weft threads along x, each an
elliptical cross-section one pitch apart (90 % of the pitch wide), passing over and under the
threads it crosses in turn (the weave repeats every two pitches); each thread's thickness varies
by a few per cent (slubs). A noise surface is white noise band-passed to its wavelengths
(isotropic, in the Fourier domain of the tile). The tile is sampled at :data:`TILE_SAMPLES` points
a side; :func:`tooth_on_texels` lays it on a canvas's texels, low-passed to the texel size
(Gaussian, sigma half a texel) so that a coarse canvas holds no aliased weave.

The definitions and tiles live in :mod:`common.surfaces` (numpy only: the 1 kHz servo process
builds the tile it feels from the name, :mod:`paintapp.haptics.contact`); this module lays them on
a canvas's texels.
"""

from __future__ import annotations

import functools

import numpy as np

from common.surfaces import (
    DEFAULT_SURFACE,
    SMOOTH,
    SURFACES,
    TILE_SAMPLES,
    SurfaceSpec,
    blurred_tile,
    relief_m,
    sample_tile,
    surface_names,
    surface_spec,
    surface_tile,
)

__all__ = [
    "DEFAULT_SURFACE",
    "SMOOTH",
    "SURFACES",
    "TILE_SAMPLES",
    "SurfaceSpec",
    "block_mean",
    "blurred_tile",
    "canvas_tooth",
    "relief_m",
    "sample_tile",
    "surface_names",
    "surface_spec",
    "surface_tile",
    "tooth_on_texels",
]


def tooth_on_texels(
    name: str, pixels: tuple[int, int], texel_m: tuple[float, float], box=None
) -> np.ndarray:
    """Surface ``name``'s heights at the centres of a canvas's texels, (H, W) float32 metres
    (canvas row 0 at the bottom), low-passed to the texel (module docstring); or over the texel
    box (x0, y0, x1, y1) alone. Zeros for ``smooth``."""
    x0, y0, x1, y1 = box if box is not None else (0, 0, pixels[0], pixels[1])
    spec = surface_spec(name)
    if spec.flat:
        return np.zeros((y1 - y0, x1 - x0), np.float32)
    tile = blurred_tile(name, 0.5 * min(texel_m))
    x = (np.arange(x0, x1) + 0.5) * texel_m[0]
    y = (np.arange(y0, y1) + 0.5) * texel_m[1]
    period = spec.tile_mm * 1e-3
    out = np.empty((y1 - y0, x1 - x0), np.float32)
    step = max(1, (1 << 20) // max(1, x1 - x0))
    for r in range(0, y1 - y0, step):
        rows = slice(r, min(y1 - y0, r + step))
        out[rows] = sample_tile(tile, period, x[None, :], y[rows, None])
    return out


@functools.lru_cache(maxsize=2)
def canvas_tooth(name: str, pixels: tuple[int, int], texel_m: tuple[float, float]) -> np.ndarray:
    """:func:`tooth_on_texels` over a whole canvas, kept (read only) for the last two canvases
    asked for: the copies of a canvas (the window's display copy, undo snapshots) share it."""
    tooth = tooth_on_texels(name, pixels, texel_m)
    tooth.flags.writeable = False
    return tooth


def block_mean(heights: np.ndarray, factor: int, shape: tuple[int, int]) -> np.ndarray:
    """(H, W) ``heights`` averaged over ``factor`` x ``factor`` blocks into ``shape`` = (w, h)
    texels (the last row and column of blocks over what they hold), float32."""
    if factor == 1:
        return np.ascontiguousarray(heights, np.float32)
    w, h = shape
    rows, cols = heights.shape
    padded = np.zeros((h * factor, w * factor))
    held = np.zeros_like(padded)
    padded[:rows, :cols] = heights
    held[:rows, :cols] = 1.0
    sums = padded.reshape(h, factor, w, factor).sum(axis=(1, 3))
    counts = held.reshape(h, factor, w, factor).sum(axis=(1, 3))
    return (sums / np.maximum(counts, 1.0)).astype(np.float32)
