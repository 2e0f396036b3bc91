"""Band-averaged Kubelka-Munk tables and the CPU reference of the canvas colour.

The renderer mixes paint per *band* (a few wide wavelength intervals) instead of per 5 nm sample.
:class:`Bands` averages spectra into bands and gives the band -> linear RGB matrix; a
:class:`BandTable` holds, for an ordered list of pigments (a canvas's channels), K and S per band,
the ground reflectance per band and that matrix. The same table feeds the shader uniforms and
:func:`canvas_linear_rgb`, the CPU reference the renderer is tested against.

Within a band the reflectance is treated as constant, so ``RGB = band_to_rgb @ R_band`` is exact
for band-constant spectra; masstones stay within a few thousandths of their full-spectral colour.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from paintapp.pigments.kubelka_munk import (
    GROUND_REFLECTANCE,
    ks_ratio_from_reflectance,
    mix_ks,
    reflectance_infinite,
    reflectance_layer,
)
from paintapp.pigments.library import Pigment, PigmentLibrary
from paintapp.pigments.spectra import WAVELENGTHS_NM, spectral_to_rgb_matrix, xyz_weights

if TYPE_CHECKING:  # the canvas is read, not imported: colour sits below the canvas
    from paintapp.canvas.model import Canvas

#: Default band edges, nm: 12 bands, 25 nm wide across 425-675 nm, wider at the dim ends.
DEFAULT_EDGES_NM: tuple[float, ...] = (380.0, *range(425, 700, 25), 781.0)


@dataclass(frozen=True)
class Bands:
    """Contiguous wavelength bands; band j is ``[edges_nm[j], edges_nm[j + 1])``."""

    edges_nm: tuple[float, ...] = DEFAULT_EDGES_NM

    @property
    def count(self) -> int:
        """Number of bands N."""
        return len(self.edges_nm) - 1

    @functools.cached_property
    def _membership(self) -> np.ndarray:
        """(N, L) 0/1 matrix: which wavelength sample lies in which band."""
        index = np.searchsorted(np.asarray(self.edges_nm), WAVELENGTHS_NM, side="right") - 1
        return (index[None, :] == np.arange(self.count)[:, None]).astype(np.float64)

    def average(self, spectra: np.ndarray) -> np.ndarray:
        """Band averages of spectra (..., L) -> (..., N), weighted by D65 x (x̄ + ȳ + z̄)."""
        weight = xyz_weights().sum(axis=0)  # (L,)
        matrix = self._membership * weight[None, :]
        matrix /= matrix.sum(axis=1, keepdims=True)
        return np.asarray(spectra, np.float64) @ matrix.T

    def to_rgb_matrix(self) -> np.ndarray:
        """(3, N) matrix: linear sRGB = ``M @ R_band`` for band-constant reflectance."""
        return spectral_to_rgb_matrix() @ self._membership.T


@dataclass(frozen=True, eq=False)
class BandTable:
    """Per-band Kubelka-Munk data for an ordered list of pigments.

    Attributes:
        names: pigment names, in channel order (P,).
        k_per_m, s_per_m: absorption and scattering per band, 1/m, shape (P, N).
        ground: reflectance of the bare ground per band, shape (N,).
        band_to_rgb: band reflectance -> linear sRGB (D65), shape (3, N).
    """

    names: tuple[str, ...]
    k_per_m: np.ndarray
    s_per_m: np.ndarray
    ground: np.ndarray
    band_to_rgb: np.ndarray

    @property
    def band_count(self) -> int:
        return int(self.band_to_rgb.shape[1])

    def reflectance(
        self, concentration: np.ndarray, thickness_m: np.ndarray | None = None
    ) -> np.ndarray:
        """Band reflectance of mixtures.

        Args:
            concentration: volume fractions, shape (P, ...).
            thickness_m: layer thickness, shape (...); None for an opaque (infinitely thick) layer.

        Returns:
            Reflectance per band, shape (..., N).
        """
        k, s = mix_ks(concentration, self.k_per_m, self.s_per_m)
        if thickness_m is None:
            return reflectance_infinite(k, s)
        return reflectance_layer(k, s, thickness_m, self.ground)

    def linear_rgb(
        self, concentration: np.ndarray, thickness_m: np.ndarray | None = None
    ) -> np.ndarray:
        """Linear sRGB (D65) of mixtures, shape (..., 3); arguments as :meth:`reflectance`."""
        return self.reflectance(concentration, thickness_m) @ self.band_to_rgb.T


def band_table(
    pigments: Sequence[Pigment],
    bands: Bands | None = None,
    ground_reflectance: float = GROUND_REFLECTANCE,
) -> BandTable:
    """Build the :class:`BandTable` of ``pigments`` (in that order).

    Each pigment's masstone is averaged into bands first and K/S derived from the band reflectance,
    so an opaque band-model masstone reproduces the band-averaged masstone exactly.
    """
    bands = bands or Bands()
    n = bands.count
    k = np.zeros((len(pigments), n))
    s = np.zeros((len(pigments), n))
    for i, pigment in enumerate(pigments):
        s[i] = pigment.scattering_per_m
        k[i] = s[i] * ks_ratio_from_reflectance(bands.average(pigment.reflectance))
    return BandTable(
        names=tuple(p.name for p in pigments),
        k_per_m=k,
        s_per_m=s,
        ground=np.full(n, float(ground_reflectance)),
        band_to_rgb=bands.to_rgb_matrix(),
    )


def canvas_band_table(
    canvas: Canvas, library: PigmentLibrary, bands: Bands | None = None
) -> BandTable:
    """The :class:`BandTable` for a canvas's pigment channels (unknown names: InputError)."""
    return band_table(library.require(canvas.pigment_names), bands)


def canvas_linear_rgb(canvas: Canvas, table: BandTable, rows: slice = slice(None)) -> np.ndarray:
    """CPU reference of the unlit canvas colour: linear sRGB (D65), shape (H, W, 3) float32.

    Each texel is a Kubelka-Munk layer of its paint height and pigment concentrations over the
    ground. ``rows`` limits the work to a band of rows (for large canvases, process in strips).
    """
    paint = canvas.paint_m[:, rows].astype(np.float64)
    height = paint.sum(axis=0)
    painted = height > 0.0
    # Bare ground is one colour: only painted texels need the layer model.
    out = np.empty((*height.shape, 3), np.float32)
    out[...] = (table.ground @ table.band_to_rgb.T).astype(np.float32)
    if painted.any():
        mix = paint[:, painted] / height[painted]
        out[painted] = table.linear_rgb(mix, height[painted]).astype(np.float32)
    return out


def mix_linear_rgb(
    library: PigmentLibrary,
    amounts: Mapping[str, float],
    thickness_m: float | None = None,
    bands: Bands | None = None,
) -> np.ndarray:
    """Linear sRGB (D65) of a Kubelka-Munk mix, shape (3,).

    Args:
        library: where the pigments come from.
        amounts: pigment name -> relative volume (normalised to fractions here).
        thickness_m: layer thickness over the ground; None for an opaque layer.
        bands: use the band model of the renderer; None for the full 5 nm spectral computation.
    """
    pigments = library.require(amounts)
    total = float(sum(amounts.values()))
    c = np.array([amounts[p.name] / total for p in pigments])
    if bands is not None:
        x = None if thickness_m is None else np.asarray(thickness_m)
        return band_table(pigments, bands).linear_rgb(c, x)
    k, s = mix_ks(
        c, np.array([p.k_per_m for p in pigments]), np.array([p.s_per_m for p in pigments])
    )
    if thickness_m is None:
        r = reflectance_infinite(k, s)
    else:
        r = reflectance_layer(k, s, np.asarray(thickness_m))
    return r @ spectral_to_rgb_matrix().T
