"""How strongly an image carries a ``p``-texel lattice: the phase ratio of its gradients.

A paint transfer that treats the grid's ``k x k``-texel columns as boxes prints their edges into
the paint: colour and paint height change mostly across texel boundaries at multiples of ``k``.
The measure: for a period ``p`` and each axis, the magnitude of the forward difference along that
axis (colour: the Euclidean norm over channels) is averaged over every texel boundary of one
phase (``(index + 1) mod p``); the ratio is the largest phase mean over the median of the ``p``
phase means (infinite when only some phases change, 1 for a flat image), and
:func:`lattice_ratio` reports the larger of the two axes: about 1 without a lattice at ``p``.

A few strong edges (a stroke's sides) fall on some phases more than others, more so for longer
periods, so :func:`null_ratio` measures the image's own floor: the same gradients with their
phases dealt out at random; the median over the deals is the floor, and the share of deals at
least as high as the observed ratio says whether a lattice is there (a small share: it is).

``python -m paintapp.canvas.lattice DIR`` prints the ratios of ``DIR/preview.png`` (colour) and
``DIR/canvas.exr`` (paint height) for periods 2-12 with floors and shares, and the painting's
holes (:func:`count_holes`: texels of at most ``FILM_FLOOR_M`` enclosed by painted ones).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.ndimage import binary_fill_holes, label

from paintapp.canvas.model import FILM_FLOOR_M

PERIODS = tuple(range(2, 13))
NULL_DEALS = 200


def _boundary_lines(image: np.ndarray, period: int) -> list[np.ndarray]:
    """Per axis, the mean gradient magnitude across each texel boundary along it (colour: the
    Euclidean norm over channels), once the period is checked against the image's size."""
    img = np.asarray(image, dtype=np.float64)
    if img.ndim == 2:
        img = img[..., None]
    if period < 2 or min(img.shape[:2]) <= period:
        raise ValueError(f"need 2 <= period < image size, got {period} for {img.shape[:2]}")
    return [
        np.sqrt((np.diff(img, axis=axis) ** 2).sum(axis=2)).mean(axis=1 - axis) for axis in (0, 1)
    ]


def _phases(n: int, period: int) -> np.ndarray:
    """The lattice phase of each of ``n`` texel boundaries."""
    return (np.arange(n) + 1) % period


def _ratio(line: np.ndarray, phase: np.ndarray, period: int) -> float:
    """Largest phase mean of ``line`` over the median phase mean (module docstring)."""
    means = np.bincount(phase, line, period) / np.bincount(phase, minlength=period)
    median = float(np.median(means))
    top = float(means.max())
    return top / median if median > 0.0 else (np.inf if top > 0.0 else 1.0)


def lattice_ratio(image: np.ndarray, period: int) -> float:
    """Phase ratio (module docstring) of an (H, W) or (H, W, C) image at ``period`` texels."""
    lines = _boundary_lines(image, period)
    return max(_ratio(line, _phases(len(line), period), period) for line in lines)


def null_ratio(
    image: np.ndarray, period: int, deals: int = NULL_DEALS, seed: int = 0
) -> tuple[float, float]:
    """What the image's ratio is without a lattice (module docstring): ``(floor, share)``, the
    median ratio over ``deals`` random deals of the boundaries' phases and the fraction of deals
    whose ratio is at least :func:`lattice_ratio`'s (reproducible through ``seed``)."""
    lines = _boundary_lines(image, period)
    observed = max(_ratio(line, _phases(len(line), period), period) for line in lines)
    rng = np.random.default_rng(seed)
    dealt = np.array(
        [
            max(_ratio(line, rng.permutation(_phases(len(line), period)), period) for line in lines)
            for _ in range(deals)
        ]
    )
    return float(np.median(dealt)), float(np.mean(dealt >= observed))


def lattice_table(image: np.ndarray, periods: tuple[int, ...] = PERIODS) -> dict[int, float]:
    """:func:`lattice_ratio` for each period."""
    return {p: lattice_ratio(image, p) for p in periods}


def hole_mask(height_m: np.ndarray, floor_m: float = FILM_FLOOR_M) -> np.ndarray:
    """(H, W) bool: unpainted texels (height at most ``floor_m``) that painted texels enclose
    (not connected, through 4-neighbours, to the unpainted canvas outside the painting)."""
    painted = np.asarray(height_m) > floor_m
    return binary_fill_holes(painted) & ~painted


def count_holes(height_m: np.ndarray, floor_m: float = FILM_FLOOR_M) -> tuple[int, int]:
    """(unpainted texels inside the painting, separate holes they form): see :func:`hole_mask`."""
    holes = hole_mask(height_m, floor_m)
    return int(holes.sum()), int(label(holes)[1])


def _read_png(path: Path) -> np.ndarray:
    import OpenImageIO as oiio

    buf = oiio.ImageBuf(str(path))
    if buf.has_error or not buf.initialized:
        raise FileNotFoundError(f"cannot read {path}: {buf.geterror()}")
    return np.asarray(buf.get_pixels(oiio.FLOAT))[..., :3]


def main(argv: list[str]) -> int:
    """Print the colour and height ratios of a demo output folder, with their floors."""
    from common.errors import InputError
    from paintapp.canvas.exr import read_canvas_exr

    folder = Path(argv[0]) if argv else Path("paintapp-demo")
    try:
        images = {
            "colour": _read_png(folder / "preview.png"),
            "height": read_canvas_exr(folder / "canvas.exr").height_m,
        }
    except (OSError, InputError) as err:
        print(f"lattice: error: {err} (expected a paintapp demo folder)", file=sys.stderr)
        return 2
    print("period  colour (floor, share)   height (floor, share)")
    worst = dict.fromkeys(images, 0.0)
    for p in PERIODS:
        cells = []
        for name, img in images.items():
            ratio = lattice_ratio(img, p)
            floor, share = null_ratio(img, p)
            worst[name] = max(worst[name], ratio)
            cells.append(f"{ratio:6.3f} ({floor:5.3f}, {share:4.2f})")
        print(f"{p:6d}  " + "   ".join(cells))
    print(f"max     {worst['colour']:6.3f}{'':17}{worst['height']:6.3f}")
    print(
        f"floor: the ratio with the boundaries' phases dealt at random (median of {NULL_DEALS} "
        "deals, no lattice possible); share: the deals at least as high (near 0: a lattice)"
    )
    texels, holes = count_holes(images["height"])
    print(
        f"holes: {texels} unpainted texels (<= {FILM_FLOOR_M:g} m) inside the painting, {holes} holes"
    )
    return 0


if __name__ == "__main__":
    from common.pipes import run_tool

    run_tool(main, sys.argv[1:])
