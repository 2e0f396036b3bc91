"""Overlay geometry: the brush outline and force arrows, as triangles in canvas metres.

Lines are built as thin triangle strips (core-profile GL has no reliable wide lines), with their
width given in output pixels so they stay visible at any zoom. The painting window asks for the
same overlay twice a frame (where it is, then to draw it) and again in the frames before the
brush moves: the last few results are kept (read-only arrays), as the numpy work holds the
interpreter lock the simulation worker waits for.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

RGBA = tuple[float, float, float, float]


@dataclass(frozen=True)
class BrushOutline:
    """An ellipse at the brush tip's footprint on the canvas.

    Attributes:
        center_m: (x, y) centre, canvas metres.
        radii_m: (rx, ry) semi-axes, metres (equal for a round tip).
        angle_rad: rotation of the rx axis from +x, counter-clockwise (the brush twist).
        color: linear RGBA.
    """

    center_m: tuple[float, float]
    radii_m: tuple[float, float]
    angle_rad: float = 0.0
    color: RGBA = (1.0, 1.0, 1.0, 0.85)


@dataclass(frozen=True)
class ForceArrow:
    """An arrow from a point along a force, as in Baxter & Lin's Figs. 6-7.

    Attributes:
        origin_m: (x, y) tail of the arrow (the brush tip), canvas metres.
        force_n: force, N; its x and y components are drawn (a z component is ignored).
        metres_per_newton: arrow length per newton of in-plane force.
        color: linear RGBA.
    """

    origin_m: tuple[float, float]
    force_n: tuple[float, ...]
    metres_per_newton: float
    color: RGBA = (1.0, 0.15, 0.05, 0.95)


def _segment_quads(points: np.ndarray, width_m: float) -> np.ndarray:
    """Triangles (2 per segment) of a polyline (N, 2) drawn ``width_m`` wide, shape (6(N-1), 2)."""
    a, b = points[:-1], points[1:]
    d = b - a
    length = np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-30)[:, None]
    n = np.stack([-d[:, 1], d[:, 0]], axis=1) / length * (0.5 * width_m)
    tris = np.stack([a - n, a + n, b + n, a - n, b + n, b - n], axis=1)
    return tris.reshape(-1, 2)


def outline_triangles(outline: BrushOutline, pixel_m: float, width_px: float = 2.0) -> np.ndarray:
    """Triangles of the brush outline ring, shape (M, 2) float32, metres (read-only)."""
    return _kept(_outline_triangles, outline, pixel_m, width_px)


def arrow_triangles(arrow: ForceArrow, pixel_m: float, width_px: float = 3.0) -> np.ndarray:
    """Triangles of a force arrow (shaft and head), shape (M, 2) float32; empty for zero force
    (read-only)."""
    return _kept(_arrow_triangles, arrow, pixel_m, width_px)


def _kept(build, shape, pixel_m: float, width_px: float) -> np.ndarray:  # type: ignore[no-untyped-def]
    """``build(shape, pixel_m, width_px)``, from the last few results where the same overlay was
    asked for (an overlay whose fields are not hashable is built anew)."""
    try:
        hash(shape)
    except TypeError:
        return _read_only(build(shape, pixel_m, width_px))
    return _kept_result(build, shape, pixel_m, width_px)


@functools.lru_cache(maxsize=8)
def _kept_result(build, shape, pixel_m: float, width_px: float) -> np.ndarray:  # type: ignore[no-untyped-def]
    return _read_only(build(shape, pixel_m, width_px))


def _read_only(a: np.ndarray) -> np.ndarray:
    a.flags.writeable = False
    return a


def _outline_triangles(outline: BrushOutline, pixel_m: float, width_px: float = 2.0) -> np.ndarray:
    count = 72
    t = np.linspace(0.0, 2.0 * math.pi, count + 1)
    rx, ry = outline.radii_m
    c, s = math.cos(outline.angle_rad), math.sin(outline.angle_rad)
    x, y = rx * np.cos(t), ry * np.sin(t)
    points = np.stack([c * x - s * y, s * x + c * y], axis=1) + np.asarray(outline.center_m)
    return _segment_quads(points, width_px * pixel_m).astype(np.float32)


def _arrow_triangles(arrow: ForceArrow, pixel_m: float, width_px: float = 3.0) -> np.ndarray:
    fx, fy = float(arrow.force_n[0]), float(arrow.force_n[1])
    vector = np.array([fx, fy]) * arrow.metres_per_newton
    length = float(np.hypot(*vector))
    if not math.isfinite(length) or length < 2.0 * pixel_m:
        return np.zeros((0, 2), np.float32)
    tail = np.asarray(arrow.origin_m, np.float64)
    direction = vector / length
    normal = np.array([-direction[1], direction[0]])
    head = min(0.35 * length, 12.0 * pixel_m)
    neck = tail + direction * (length - head)
    shaft = _segment_quads(np.stack([tail, neck]), width_px * pixel_m)
    tip = tail + vector
    half = 0.5 * head
    head_tri = np.stack([neck + normal * half, neck - normal * half, tip])
    return np.concatenate([shaft, head_tri]).astype(np.float32)
