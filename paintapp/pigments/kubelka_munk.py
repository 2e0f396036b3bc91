"""Kubelka-Munk two-flux theory: absorption K, scattering S, mixing and layer reflectance.

Units: K and S are per metre of paint thickness (1/m); thicknesses are metres; reflectances are
fractions in (0, 1]. Functions broadcast over any leading shape; the last axis is the spectral
axis (wavelengths or bands).

Pigment model (a stated choice): each pigment has a *masstone* reflectance R (an opaque, infinitely
thick layer of the pure pigment) and one scattering strength ``s_per_m`` that is flat over
wavelength. Then ``S = s_per_m`` and ``K = S * (1 - R)^2 / (2 R)`` reproduces the masstone exactly,
and ``s_per_m`` sets both hiding power (how thin a layer covers the ground) and tinting strength
(how much the pigment dominates a mixture).

Mixtures add K and S weighted by volume concentration (Duncan's rule). A layer of thickness X over
a ground of reflectance Rg has (Kubelka 1948, with ``b S = sqrt(K (K + 2 S))``)::

    R = (t (S - Rg (S + K)) + Rg) / (t (S + K - Rg S) + 1),   t = tanh(b S X) / (b S)

which tends to ``R_inf = 1 + K/S - sqrt((K/S)^2 + 2 K/S)`` as X grows and to Rg as X -> 0.
"""

from __future__ import annotations

import numpy as np

#: Reflectance of the bare canvas ground (a white gesso), flat over wavelength.
GROUND_REFLECTANCE = 0.88
#: b S X beyond this is treated as infinitely thick (tanh(20) == 1 in double precision).
_THICK_LIMIT = 20.0


def ks_ratio_from_reflectance(reflectance: np.ndarray) -> np.ndarray:
    """K/S of an opaque layer with reflectance R: ``(1 - R)^2 / (2 R)``. R must be in (0, 1]."""
    r = np.asarray(reflectance, np.float64)
    return (1.0 - r) ** 2 / (2.0 * r)


def reflectance_infinite(k: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Reflectance of an opaque layer, ``1 + K/S - sqrt((K/S)^2 + 2 K/S)``; needs S > 0."""
    q = np.asarray(k, np.float64) / np.asarray(s, np.float64)
    # Written as 1 / (1 + q + sqrt(q^2 + 2q)) to avoid cancellation for large K/S.
    return 1.0 / (1.0 + q + np.sqrt(q * q + 2.0 * q))


def mix_ks(
    concentration: np.ndarray, k_per_m: np.ndarray, s_per_m: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Mixture K and S by Duncan's rule.

    Args:
        concentration: volume fractions, shape (P, ...) (P pigments, any trailing shape).
        k_per_m, s_per_m: each pigment's K and S, shape (P, N) for N wavelengths or bands.

    Returns:
        (K, S) of the mixture, each shape (..., N).
    """
    c = np.moveaxis(np.asarray(concentration, np.float64), 0, -1)  # (..., P)
    return c @ np.asarray(k_per_m, np.float64), c @ np.asarray(s_per_m, np.float64)


def reflectance_layer(
    k_per_m: np.ndarray,
    s_per_m: np.ndarray,
    thickness_m: np.ndarray,
    ground: np.ndarray | float = GROUND_REFLECTANCE,
) -> np.ndarray:
    """Reflectance of a paint layer of finite thickness over a ground (see module docstring).

    Args:
        k_per_m, s_per_m: layer K and S, shape (..., N), non-negative.
        thickness_m: layer thickness, shape (...) broadcastable against (..., N) without N.
        ground: ground reflectance, scalar or shape (N,).

    Returns:
        Reflectance, shape (..., N). Where the layer is empty (X = 0 or K = S = 0) it is the ground.
    """
    k = np.asarray(k_per_m, np.float64)
    s = np.asarray(s_per_m, np.float64)
    x = np.asarray(thickness_m, np.float64)[..., None]
    beta = np.sqrt(k * (k + 2.0 * s))
    arg = beta * x
    safe_beta = np.where(beta > 0.0, beta, 1.0)
    t = np.where(
        arg < 1e-6,
        x * (1.0 - arg * arg / 3.0),
        np.tanh(np.minimum(arg, _THICK_LIMIT)) / safe_beta,
    )
    rg = np.asarray(ground, np.float64)
    num = t * (s - rg * (s + k)) + rg
    den = t * (s + k - rg * s) + 1.0
    return num / den


def masstone_ks(reflectance: np.ndarray, s_per_m: float) -> tuple[np.ndarray, np.ndarray]:
    """(K, S) per wavelength of a pigment from its masstone reflectance and scattering, 1/m."""
    s = np.full(np.shape(reflectance), float(s_per_m))
    return s * ks_ratio_from_reflectance(reflectance), s
