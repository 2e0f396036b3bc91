"""Spectra and colourimetry for pigments: upsampling sRGB to reflectance, spectrum to linear RGB.

Everything colour-related is computed under one stated viewing condition:

- illuminant **CIE D65** (``colour.SDS_ILLUMINANTS["D65"]``),
- observer **CIE 1931 2° standard observer**,
- output **linear scene-referred RGB with sRGB / Rec.709 primaries and a D65 white point**
  (no transfer function applied). A perfect white reflector (R = 1 at every wavelength) maps to
  RGB ≈ (1, 1, 1), so the values are diffuse reflectance as seen under unit D65 light.

Spectra are sampled on :data:`WAVELENGTHS_NM` (380-780 nm every 5 nm). An sRGB colour becomes a
spectrum with the Jakob & Hanika (2019) sigmoid model (``colour.recovery.XYZ_to_sd_Jakob2019``):
it runs offline (once per colour), matches the colour exactly under D65, and gives smooth spectra
that reach close to 0 and 1, which Kubelka-Munk mixing needs to make clean secondaries. The fit is
cached per colour, in memory and on disk (see :mod:`paintapp.pigments.spectrum_cache`).

colour-science is imported only to compute what the on-disk cache does not hold yet: the tables
(colour matching functions, illuminant, RGB matrix) and each colour's spectrum, which are kept
there as computed, so a cached value is the very value colour-science gave.
"""

from __future__ import annotations

import functools

import numpy as np

from paintapp.pigments.spectrum_cache import (
    load_coefficients,
    load_table,
    store_coefficients,
    store_table,
)

#: Wavelength samples of every spectrum in this package, nm. Shape (L,) = (81,).
WAVELENGTHS_NM: np.ndarray = np.arange(380.0, 781.0, 5.0)
ILLUMINANT_NAME = "D65"
OBSERVER_NAME = "CIE 1931 2 Degree Standard Observer"
RGB_SPACE_NAME = "sRGB"
#: Reflectances are kept in [MIN_REFLECTANCE, MAX_REFLECTANCE] so K/S stays finite and positive.
MIN_REFLECTANCE = 1e-3
MAX_REFLECTANCE = 0.999
#: :data:`WAVELENGTHS_NM` as colour-science's spectral shape (start, end, interval), nm.
_SHAPE_NM = (380.0, 780.0, 5.0)
_SHAPE_KEY = "380-780-5"


def _shape():
    import colour

    return colour.SpectralShape(*_SHAPE_NM)


@functools.cache
def _cmfs_and_illuminant() -> tuple[np.ndarray, np.ndarray]:
    """(L, 3) colour matching functions and (L,) D65 power on :data:`WAVELENGTHS_NM`."""
    n = len(WAVELENGTHS_NM)
    keys = (f"cmfs:{OBSERVER_NAME}:{_SHAPE_KEY}", f"illuminant:{ILLUMINANT_NAME}:{_SHAPE_KEY}")
    cmfs, illuminant = load_table(keys[0], (n, 3)), load_table(keys[1], (n,))
    if cmfs is None or illuminant is None:
        import colour

        cmfs = np.asarray(
            colour.MSDS_CMFS[OBSERVER_NAME].copy().align(_shape()).values, dtype=np.float64
        )
        illuminant = np.asarray(
            colour.SDS_ILLUMINANTS[ILLUMINANT_NAME].copy().align(_shape()).values, np.float64
        )
        store_table(keys[0], cmfs)
        store_table(keys[1], illuminant)
    return cmfs, illuminant


@functools.cache
def xyz_weights() -> np.ndarray:
    """Per-wavelength weights turning a reflectance into CIE XYZ, shape (3, L).

    ``XYZ = xyz_weights() @ R``; normalised so a perfect reflector has Y = 1.
    """
    cmfs, illum = _cmfs_and_illuminant()
    weights = (cmfs * illum[:, None]).T  # (3, L)
    return weights / weights[1].sum()


@functools.cache
def xyz_to_linear_rgb_matrix() -> np.ndarray:
    """3x3 matrix from CIE XYZ (D65) to linear sRGB / Rec.709 RGB."""
    key = f"xyz_to_rgb:{RGB_SPACE_NAME}"
    matrix = load_table(key, (3, 3))
    if matrix is None:
        import colour

        matrix = np.asarray(colour.RGB_COLOURSPACES[RGB_SPACE_NAME].matrix_XYZ_to_RGB, np.float64)
        store_table(key, matrix)
    return matrix


@functools.cache
def spectral_to_rgb_matrix() -> np.ndarray:
    """(3, L) matrix: linear RGB = ``spectral_to_rgb_matrix() @ R`` for a reflectance R (L,)."""
    return xyz_to_linear_rgb_matrix() @ xyz_weights()


def reflectance_to_linear_rgb(reflectance: np.ndarray) -> np.ndarray:
    """Linear sRGB (D65) of reflectance spectra, shape (..., L) -> (..., 3)."""
    return np.asarray(reflectance, np.float64) @ spectral_to_rgb_matrix().T


def srgb_decode(encoded: np.ndarray) -> np.ndarray:
    """sRGB transfer function inverse (IEC 61966-2-1): encoded [0, 1] -> linear."""
    c = np.asarray(encoded, np.float64)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def srgb_encode(linear: np.ndarray) -> np.ndarray:
    """sRGB transfer function (IEC 61966-2-1): linear -> encoded, input clipped to [0, 1]."""
    c = np.clip(np.asarray(linear, np.float64), 0.0, 1.0)
    return np.where(c <= 0.0031308, c * 12.92, 1.055 * np.power(c, 1.0 / 2.4) - 0.055)


def _fit_jakob_spectrum(srgb: tuple[float, float, float]) -> np.ndarray:
    """The Jakob 2019 spectrum of an sRGB colour on :data:`WAVELENGTHS_NM`, unclipped (L,),
    from the cached coefficients or a new fit (colour-science)."""
    import colour
    import colour.recovery.jakob2019

    shape = colour.recovery.jakob2019.SPECTRAL_SHAPE_JAKOB2019
    cmfs = colour.MSDS_CMFS[OBSERVER_NAME].copy().align(shape)
    coefficients = load_coefficients(srgb)
    if coefficients is None:
        illuminant = colour.SDS_ILLUMINANTS[ILLUMINANT_NAME].copy().align(shape)
        xyz = np.linalg.solve(xyz_to_linear_rgb_matrix(), srgb_decode(np.asarray(srgb)))
        found, _ = colour.recovery.find_coefficients_Jakob2019(xyz, cmfs, illuminant)
        coefficients = [float(c) for c in found]
        store_coefficients(srgb, coefficients)
    sd = colour.recovery.sd_Jakob2019(np.asarray(coefficients), cmfs.shape)
    return np.asarray(sd.copy().align(_shape()).values, np.float64)


@functools.lru_cache(maxsize=256)
def _jakob_reflectance(srgb: tuple[float, float, float]) -> np.ndarray:
    key = f"jakob2019:{OBSERVER_NAME}:{ILLUMINANT_NAME}:{_SHAPE_KEY}:" + ",".join(
        f"{c:.6f}" for c in srgb
    )
    values = load_table(key, WAVELENGTHS_NM.shape)
    if values is None:
        values = _fit_jakob_spectrum(srgb)
        store_table(key, values)
    values = np.clip(values, MIN_REFLECTANCE, MAX_REFLECTANCE)
    values.setflags(write=False)
    return values


def srgb_to_reflectance(srgb: tuple[float, float, float]) -> np.ndarray:
    """Smooth reflectance spectrum (L,) whose colour under D65 is the given sRGB colour.

    Args:
        srgb: sRGB-encoded (gamma) colour, each component in [0, 1].

    Returns:
        A read-only array of reflectances on :data:`WAVELENGTHS_NM`, within
        [MIN_REFLECTANCE, MAX_REFLECTANCE]. Cached per colour.
    """
    key = tuple(round(float(c), 6) for c in srgb)
    return _jakob_reflectance(key)  # type: ignore[arg-type]


def resample_reflectance(wavelengths_nm: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Measured reflectance resampled onto :data:`WAVELENGTHS_NM`, shape (L,).

    Linear interpolation inside the measured range, constant extrapolation outside it; the result
    is clipped to [MIN_REFLECTANCE, MAX_REFLECTANCE].
    """
    resampled = np.interp(WAVELENGTHS_NM, np.asarray(wavelengths_nm), np.asarray(values))
    return np.clip(resampled, MIN_REFLECTANCE, MAX_REFLECTANCE)
