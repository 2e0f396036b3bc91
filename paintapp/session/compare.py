"""How far apart two replays of the same strokes are: colour, paint height and force trace.

Used to compare fidelities (draft and standard against high) and model choices (``auto`` against a
full 3D grid everywhere). All three figures are RMS differences over the whole canvas or trace:

- ``colour_rms``: RMS over texels and the R, G, B channels of the unlit linear colour
  (:func:`paintapp.canvas.exr.unlit_rgba`; 0..1 per channel);
- ``height_rms_mm``: RMS of the paint height difference (all pigments), mm; and
  ``height_rms_rel``, that divided by the reference's RMS height over its painted texels;
- ``force_rms_rel``: RMS over servo ticks of the force difference's magnitude, divided by the RMS
  force magnitude of the reference (None when the reference has no force).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from paintapp.canvas.exr import unlit_rgba
from paintapp.canvas.model import Canvas
from paintapp.pigments.library import PigmentLibrary, load_pigment_library


@dataclass(frozen=True)
class ReplaySnapshot:
    """What a replay left: the unlit colour (H, W, 3), the paint height (H, W, m) and the force
    trace (ticks, 7)."""

    rgb: np.ndarray
    height_m: np.ndarray
    forces: np.ndarray


def snapshot(canvas: Canvas, forces: np.ndarray, library: PigmentLibrary | None = None):
    """The :class:`ReplaySnapshot` of a painted canvas and its force trace."""
    rgb = unlit_rgba(canvas, library or load_pigment_library())[..., :3].astype(np.float64)
    height = canvas.paint_m.sum(axis=0, dtype=np.float64)
    return ReplaySnapshot(rgb, height, np.asarray(forces, dtype=float))


def _rms(x: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.square(x)))) if x.size else 0.0


def compare_replays(actual: ReplaySnapshot, reference: ReplaySnapshot) -> dict[str, float | None]:
    """The difference figures of ``actual`` against ``reference`` (see the module docstring)."""
    if actual.rgb.shape != reference.rgb.shape:
        raise ValueError(f"canvas sizes differ: {actual.rgb.shape} != {reference.rgb.shape}")
    painted = reference.height_m[reference.height_m > 0.0]
    height_diff = actual.height_m - reference.height_m
    out: dict[str, float | None] = {
        "colour_rms": _rms(actual.rgb - reference.rgb),
        "height_rms_mm": 1e3 * _rms(height_diff),
        "height_rms_rel": _rms(height_diff) / _rms(painted) if painted.size else None,
        "force_rms_rel": None,
    }
    a, b = actual.forces, reference.forces
    n = min(len(a), len(b))
    if n:
        ref = _rms(np.linalg.norm(b[:n, 1:4], axis=1))
        diff = _rms(np.linalg.norm(a[:n, 1:4] - b[:n, 1:4], axis=1))
        out["force_rms_rel"] = diff / ref if ref > 0.0 else None
    return out
