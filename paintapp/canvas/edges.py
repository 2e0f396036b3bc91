"""How wide a painting's edges are: the texels of its ramps over the length of its outline.

The measure, on the total paint thickness of each texel (the sum over pigments, metres):

- ``T90``: the 90th percentile of the thickness over the painted texels (thickness above
  ``FILM_FLOOR_M`` = 1e-7 m; numpy's default, linear, percentile);
- ramp texels: the texels whose thickness lies in ``[0.05, 0.5] x T90`` (both ends included);
- contour texels: the length, in texels, of the 50 % contour: the texels with a thickness of at
  least ``0.5 T90`` that have a 4-neighbour (inside the canvas) below ``0.5 T90``;
- edge width = ramp texels / contour texels, in texels.

A hard edge (full thickness next to bare canvas) has no ramp texels: width 0. An edge whose
thickness falls linearly from ``T90`` to 0 over ``N`` texels, straight along a texel axis, has
``0.45 N`` ramp texels per contour texel: width ``0.45 N``. Along a slanted edge the contour
counts ``max(|cos a|, |sin a|)`` texels per texel of length (``a``: the edge's angle to an
axis), so round shapes measure a little wider: a disc's contour counts ``4 sqrt(2) r`` texels
against its circumference ``2 pi r``, 0.90 of it, and a ramped disc measures about ``0.50 N``.

A canvas with no painted texel, or whose paint has no 50 % contour (the same thickness
everywhere), has no edge to measure: its width is NaN (not 0, which would read as a perfectly
sharp edge), with ``contour_texels`` 0 (:attr:`EdgeWidth.has_edge` is False).

``python -m paintapp.canvas.edges DIR`` prints the edge width of ``DIR/canvas.exr`` (as
``paintapp demo --out DIR`` writes it) on one line.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from paintapp.canvas.model import FILM_FLOOR_M

#: The ramp's thickness band and the contour's level, fractions of T90.
RAMP_LOW, RAMP_HIGH = 0.05, 0.5
CONTOUR_LEVEL = 0.5
#: The percentile of the painted texels' thickness that sets the scale.
SCALE_PERCENTILE = 90.0


@dataclass(frozen=True)
class EdgeWidth:
    """The edge width of a painting (module docstring).

    Attributes:
        width_texels: ramp texels over contour texels; NaN without an edge.
        t90_m: the 90th percentile of the painted texels' thickness, metres (0 without paint).
        ramp_texels: texels with a thickness in ``[0.05, 0.5] x T90``.
        contour_texels: texels of at least ``0.5 T90`` with a 4-neighbour below it.
    """

    width_texels: float
    t90_m: float
    ramp_texels: int
    contour_texels: int

    @property
    def has_edge(self) -> bool:
        """Whether there was a 50 % contour to measure against."""
        return self.contour_texels > 0

    def describe(self, texel_m: float | None = None) -> str:
        """One line: the width (and in mm with ``texel_m``, the texel's size in metres)."""
        if not self.has_edge:
            return (
                f"edge width: none (no 50 % contour; T90 {1e3 * self.t90_m:.4g} mm, "
                f"{self.ramp_texels} ramp texels)"
            )
        mm = f" ({1e3 * self.width_texels * texel_m:.3g} mm)" if texel_m else ""
        return (
            f"edge width {self.width_texels:.3g} texels{mm}: {self.ramp_texels} texels at "
            f"{100 * RAMP_LOW:g}-{100 * RAMP_HIGH:g} % of T90 = {1e3 * self.t90_m:.4g} mm, "
            f"{self.contour_texels} on the {100 * CONTOUR_LEVEL:g} % contour"
        )


def contour_mask(thickness_m: np.ndarray, level_m: float) -> np.ndarray:
    """(H, W) bool: texels of at least ``level_m`` with a 4-neighbour inside the array below it."""
    above = np.asarray(thickness_m) >= level_m
    below = ~above
    edge = np.zeros_like(above)
    edge[1:, :] |= below[:-1, :]
    edge[:-1, :] |= below[1:, :]
    edge[:, 1:] |= below[:, :-1]
    edge[:, :-1] |= below[:, 1:]
    return above & edge


def edge_width(thickness_m: np.ndarray) -> EdgeWidth:
    """The edge width (module docstring) of an (H, W) map of total paint thickness, metres."""
    thickness = np.asarray(thickness_m, dtype=np.float64)
    if thickness.ndim != 2:
        raise ValueError(f"expected an (H, W) thickness map, got shape {thickness.shape}")
    painted = thickness[thickness > FILM_FLOOR_M]
    if painted.size == 0:
        return EdgeWidth(math.nan, 0.0, 0, 0)
    t90 = float(np.percentile(painted, SCALE_PERCENTILE))
    ramp = int(np.count_nonzero((thickness >= RAMP_LOW * t90) & (thickness <= RAMP_HIGH * t90)))
    contour = int(np.count_nonzero(contour_mask(thickness, CONTOUR_LEVEL * t90)))
    width = ramp / contour if contour else math.nan
    return EdgeWidth(width, t90, ramp, contour)


def paint_edge_width(paint_m: np.ndarray) -> EdgeWidth:
    """The edge width of a canvas's paint, (P, H, W) metres per pigment (summed over P)."""
    return edge_width(np.asarray(paint_m).sum(axis=0, dtype=np.float64))


def main(argv: list[str]) -> int:
    """Print the edge width of a demo output folder's ``canvas.exr``."""
    from common.errors import InputError
    from paintapp.canvas.exr import read_canvas_exr

    folder = Path(argv[0]) if argv else Path("paintapp-demo")
    try:
        canvas = read_canvas_exr(folder / "canvas.exr")
    except (OSError, InputError) as err:
        print(f"edges: error: {err} (expected a paintapp demo folder)", file=sys.stderr)
        return 2
    print(paint_edge_width(canvas.paint_m).describe(canvas.texel_size_m[0]))
    return 0


if __name__ == "__main__":
    from common.pipes import run_tool

    run_tool(main, sys.argv[1:])
