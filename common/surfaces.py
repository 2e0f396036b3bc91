"""Canvas surfaces: the tooth of a ground (gesso, linen, cotton duck, paper) as a periodic tile.

The surfaces' definitions and their tiles, numpy only: the canvas lays them on its texels
(:mod:`paintapp.canvas.surfaces`, which says what each surface is), and the 1 kHz servo process
builds the tile it feels from a surface's name (:mod:`paintapp.haptics.contact`). A tile is
generated procedurally and deterministically (a fixed seed per surface) and repeats seamlessly
every ``tile_mm``; heights are metres along +z, zero-mean, with peak-to-valley ``relief_um``.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from common.errors import InputError

#: Samples a side of a surface's tile.
TILE_SAMPLES = 512
#: The flat surface (no tooth), and the default of a new canvas.
SMOOTH = "smooth"
DEFAULT_SURFACE = SMOOTH


@dataclass(frozen=True)
class SurfaceSpec:
    """One bundled surface.

    Attributes:
        name: its name (``--surface``; stored with the canvas).
        label: its name in words.
        kind: ``flat``, ``weave`` or ``noise``.
        tile_mm: period of the tile along x and y, mm.
        relief_um: peak-to-valley height of the tile, micrometres.
        pitch_mm: thread pitch of a weave (centre to centre), mm.
        band_mm: (shortest, longest) wavelength of a noise surface, mm.
        seed: the random seed of its irregularities.
    """

    name: str
    label: str
    kind: str
    tile_mm: float = 1.0
    relief_um: float = 0.0
    pitch_mm: float = 0.0
    band_mm: tuple[float, float] = (0.0, 0.0)
    seed: int = 0

    @property
    def flat(self) -> bool:
        """True for the surface without tooth."""
        return self.kind == "flat" or self.relief_um == 0.0

    def describe(self) -> str:
        """``fine linen: plain weave, pitch 0.35 mm, relief 40 um`` and the like."""
        if self.flat:
            return f"{self.label}: no tooth"
        if self.kind == "weave":
            what = f"plain weave, thread pitch {self.pitch_mm:g} mm"
        else:
            what = f"wavelengths {self.band_mm[0]:g}-{self.band_mm[1]:g} mm"
        return f"{self.label}: {what}, relief {self.relief_um:g} um, tile {self.tile_mm:g} mm"


SURFACES: dict[str, SurfaceSpec] = {
    s.name: s
    for s in (
        SurfaceSpec(SMOOTH, "smooth", "flat"),
        SurfaceSpec("gesso", "smooth gesso", "noise", 16.0, 8.0, band_mm=(0.15, 2.0), seed=11),
        SurfaceSpec("fine_linen", "fine linen", "weave", 14.0, 40.0, pitch_mm=0.35, seed=23),
        SurfaceSpec("cotton_duck", "cotton duck", "weave", 24.0, 120.0, pitch_mm=1.0, seed=37),
        SurfaceSpec(
            "cold_press", "cold-press paper", "noise", 20.0, 70.0, band_mm=(0.3, 3.0), seed=41
        ),
    )
}


def surface_names() -> list[str]:
    """The bundled surfaces' names, ``smooth`` first."""
    return list(SURFACES)


def surface_spec(name: str, key: str = "--surface") -> SurfaceSpec:
    """The bundled surface ``name``; InputError naming ``key`` for an unknown one."""
    spec = SURFACES.get(str(name).strip().lower())
    if spec is None:
        raise InputError(f"unknown surface {name!r}; known: {', '.join(SURFACES)}", key=key)
    return spec


@functools.lru_cache(maxsize=8)
def surface_tile(name: str) -> np.ndarray:
    """The tile of surface ``name``: (N, N) float64 heights, metres, zero-mean, peak-to-valley
    ``relief_um``; row ``j`` is y = j L / N, column ``i`` x = i L / N (L = ``tile_mm``).
    Deterministic; cached and read only. Zeros for ``smooth``."""
    spec = surface_spec(name)
    n = TILE_SAMPLES
    if spec.flat:
        tile = np.zeros((n, n))
    else:
        raw = _weave(spec, n) if spec.kind == "weave" else _noise(spec, n)
        raw -= raw.min()
        tile = raw * (spec.relief_um * 1e-6 / raw.max())
        tile -= tile.mean()
    tile.flags.writeable = False
    return tile


def _frequencies(n: int, tile_mm: float) -> tuple[np.ndarray, np.ndarray]:
    """(fy, fx) spatial frequencies (1/mm) of an (n, n) tile's FFT, broadcastable."""
    f = np.fft.fftfreq(n, d=tile_mm / n)
    return f[:, None], f[None, :]


def _noise(spec: SurfaceSpec, n: int) -> np.ndarray:
    """White noise band-passed to ``band_mm`` (smooth edges); cold-press gets rounded tops."""
    rng = np.random.default_rng(spec.seed)
    fy, fx = _frequencies(n, spec.tile_mm)
    f = np.hypot(fx, fy)
    lo, hi = 1.0 / spec.band_mm[1], 1.0 / spec.band_mm[0]
    with np.errstate(divide="ignore"):
        band = np.exp(-0.5 * (np.log(np.where(f > 0, f, 1e-9) / math.sqrt(lo * hi)) / 0.6) ** 2)
    band *= (f >= 0.5 * lo) & (f <= 2.0 * hi)
    field = np.fft.ifft2(np.fft.fft2(rng.standard_normal((n, n))) * band).real
    field /= field.std()
    if spec.name == "cold_press":
        field = np.tanh(1.2 * field)  # the paper's bumps are rounded, its hollows open
    return field


def _weave(spec: SurfaceSpec, n: int) -> np.ndarray:
    """A plain weave (module docstring) on an (n, n) tile, in units of the thread radius."""
    rng = np.random.default_rng(spec.seed)
    threads = round(spec.tile_mm / spec.pitch_mm)  # a whole, even number of threads a tile
    threads += threads % 2
    pitch = spec.tile_mm / threads
    s = (np.arange(n) + 0.5) * (spec.tile_mm / n) / pitch  # thread units
    index = np.floor(s).astype(np.int64)
    offset = s - index - 0.5  # across the thread, [-0.5, 0.5)
    thickness = 1.0 + 0.08 * rng.standard_normal((2, threads))  # slubs: warp, weft
    half_width = 0.45

    def profile(off: np.ndarray, scale: np.ndarray) -> np.ndarray:
        inside = np.maximum(1.0 - (off / half_width) ** 2, 0.0)
        return np.where(inside > 0, scale * np.sqrt(inside), -np.inf)

    # warp i (along y, at x = i + 1/2) is over weft j where i + j is even
    warp_x = profile(offset, thickness[0, index])[None, :]
    weft_y = profile(offset, thickness[1, index])[:, None]
    warp_rise = np.cos(math.pi * (s[:, None] - 0.5 - index[None, :]))
    weft_rise = -np.cos(math.pi * (s[None, :] - 0.5 - index[:, None]))
    height = np.maximum(0.5 * warp_rise + warp_x, 0.5 * weft_rise + weft_y)
    floor = -0.9  # the gaps between threads
    height = np.where(np.isfinite(height), np.maximum(height, floor), floor)
    fibres = _blurred(rng.standard_normal((n, n)), 0.02 / (spec.tile_mm / n))
    height += 0.05 * fibres / fibres.std()
    return _blurred(height, 0.03 * pitch / (spec.tile_mm / n))


def _blurred(tile: np.ndarray, sigma_samples: float) -> np.ndarray:
    """A periodic tile low-passed by a Gaussian of ``sigma_samples`` (in the Fourier domain)."""
    if sigma_samples <= 0.0:
        return tile
    n = tile.shape[0]
    f = np.fft.fftfreq(n)
    gain = np.exp(-2.0 * (math.pi * sigma_samples) ** 2 * (f[:, None] ** 2 + f[None, :] ** 2))
    return np.fft.ifft2(np.fft.fft2(tile) * gain).real


def blurred_tile(name: str, sigma_m: float) -> np.ndarray:
    """The tile of ``name`` low-passed by a Gaussian of ``sigma_m`` metres, (N, N) float64."""
    spec = surface_spec(name)
    return _blurred(np.array(surface_tile(name)), sigma_m / (spec.tile_mm * 1e-3 / TILE_SAMPLES))


def sample_tile(tile: np.ndarray, period_m: float, x_m: np.ndarray, y_m: np.ndarray) -> np.ndarray:
    """Bilinear, periodic samples of ``tile`` (rows y, columns x, period ``period_m``) at points
    ``x_m`` (along the last axis) and ``y_m`` broadcast together, metres."""
    n = tile.shape[0]
    u = np.asarray(x_m, dtype=float) * (n / period_m)
    v = np.asarray(y_m, dtype=float) * (n / period_m)
    i0, j0 = np.floor(u), np.floor(v)
    fu, fv = u - i0, v - j0
    i0 = i0.astype(np.int64) % n
    j0 = j0.astype(np.int64) % n
    i1, j1 = (i0 + 1) % n, (j0 + 1) % n
    return (1.0 - fv) * ((1.0 - fu) * tile[j0, i0] + fu * tile[j0, i1]) + fv * (
        (1.0 - fu) * tile[j1, i0] + fu * tile[j1, i1]
    )


def relief_m(name: str) -> float:
    """Peak-to-valley height of surface ``name``'s tile, metres (0 for ``smooth``)."""
    return surface_spec(name).relief_um * 1e-6
