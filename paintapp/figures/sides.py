"""``paintapp figures sides --out F.png``: what the 3D paint grid's sides do to the force and the paint.

The square probe dragged at 0.076 m/s through 0.5 mm of wet cadmium red (0.1 mm texels, two a
cell), four times: the default grid (32 x 32 x 12 cells over two brush widths) with free-slip
lateral walls re-centred on the tip by whole cells (``follow = "cells"``, the default before),
the same grid following the tip continuously (``follow = "continuous"``, the default now: the
tip keeps its place in its cell, and the walls their distance), the same grid with open sides (``sides = "open"``,
:mod:`paintapp.paint.far_field`), and a slip grid twice as wide (64 x 64 x 12 over four brush
widths, the same cells, by whole cells) as the reference the narrow ones should come near. The plot shows the drag and the lift along the
stroke and the paint height across it (the mean over the middle of the stroke); the mean forces
over the middle half of the stroke, and how far each grid is off the wide one, are printed.
"""

from __future__ import annotations

import argparse
import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from common.errors import InputError

if TYPE_CHECKING:  # the painting side loads only when the figure is made
    from paintapp.paint.paint_scene import FollowKind, SideKind

RED = "cadmium_red"
TEXEL_M = 1e-4
#: The canvas (texels) and the painted block on it: rows, columns.
CANVAS = (560, 200)
PAINTED = (slice(30, 170), slice(20, 540))
#: The stroke: from, to (m), duration (s); the columns averaged across it.
START_M, END_M, DURATION_S = (0.006, 0.01), (0.05, 0.01), 0.044 / 0.076
MIDDLE = slice(250, 450)
#: The four grids: label, sides, lateral cells, span (brush widths), how they follow the tip.
CASES: tuple[tuple[str, SideKind, int, float, FollowKind], ...] = (
    ("slip walls, 32 cells, by cells", "slip", 32, 2.0, "cells"),
    ("slip walls, 32 cells, following", "slip", 32, 2.0, "continuous"),
    ("open sides, 32 cells", "open", 32, 2.0, "cells"),
    ("slip walls, 64 cells (reference)", "slip", 64, 4.0, "cells"),
)


@dataclass
class DragResult:
    """One drag: time (s) and force (N, x y z) of each sample, the paint height across the
    stroke (m, per canvas row), and the paint inventory's relative drift."""

    label: str
    t_s: np.ndarray
    force_n: np.ndarray
    across_m: np.ndarray
    drift: float

    def middle(self) -> np.ndarray:
        """The force (N) over the middle half of the stroke."""
        n = len(self.force_n)
        return self.force_n[n // 4 : 3 * n // 4]

    def mean_force(self) -> np.ndarray:
        """Mean force over the middle half of the stroke, N."""
        return self.middle().mean(axis=0)

    def jitter(self) -> np.ndarray:
        """RMS change of the force from one sample to the next over the middle half, N: what a
        hand feels as buzz."""
        return np.sqrt(np.mean(np.diff(self.middle(), axis=0) ** 2, axis=0))


def drag(
    label: str, sides: SideKind, cells: int, span: float, follow: FollowKind = "cells"
) -> DragResult:
    """Drag the probe through the wet red with the given grid (module docstring)."""
    from brushes import StylusSample
    from paintapp.canvas.model import Canvas
    from paintapp.paint.paint_scene import load_paint_scene
    from paintapp.session.painting import PaintingSession, paint_inventory

    scene = dataclasses.replace(
        load_paint_scene("default"),
        sides=sides,
        cells=(cells, cells, 12),
        span=span,
        margin_cells=cells // 2 - 1,
        follow=follow,
    )
    w, h = CANVAS
    layer = np.zeros((1, h, w), np.float32)
    layer[(0, *PAINTED)] = 5e-4
    canvas = Canvas(
        (w, h), (w * TEXEL_M, h * TEXEL_M), (RED,), layer, (layer[0] > 0).astype(np.float32)
    )
    session = PaintingSession(canvas, "square_probe", scene)
    before = paint_inventory(canvas, session.reservoir)[RED]
    n = round(DURATION_S * 60) + 1
    times, forces = [], []
    for i in range(n):
        s = i / (n - 1)
        pressure = 0.0 if i in (0, n - 1) else 1.0
        xy = np.asarray(START_M) + s * (np.asarray(END_M) - np.asarray(START_M))
        step = session.sample(StylusSample(s * DURATION_S, np.array([*xy, 0.0]), pressure))
        times.append(s * DURATION_S)
        forces.append(step.force_n.copy())
    drift = abs(paint_inventory(canvas, session.reservoir)[RED] - before) / before
    across = canvas.height_m[:, MIDDLE].astype(float).mean(axis=1)
    return DragResult(label, np.array(times), np.array(forces), across, drift)


def plot(results: list[DragResult], out: Path) -> None:
    """Draw the drag, the lift and the height across the stroke into a PNG at ``out``."""
    from paintapp.figures._sweep_plot import pyplot, save_figure

    plt = pyplot()
    fig, (ax_x, ax_z, ax_h) = plt.subplots(3, 1, figsize=(8.0, 9.0))
    styles = ("C0", "C2", "C3", "k")
    for r, color in zip(results, styles, strict=True):
        ax_x.plot(r.t_s * 1e3, -r.force_n[:, 0] * 1e3, color=color, label=r.label)
        ax_z.plot(r.t_s * 1e3, r.force_n[:, 2] * 1e3, color=color, label=r.label)
        rows = (np.arange(len(r.across_m)) + 0.5) * TEXEL_M * 1e3
        ax_h.plot(rows, r.across_m * 1e6, color=color, label=r.label)
    ax_x.set(
        xlabel="time (ms)", ylabel="drag (mN)", title="The square probe through 0.5 mm of wet paint"
    )
    ax_z.set(xlabel="time (ms)", ylabel="lift (mN)")
    ax_h.set(xlabel="across the stroke (mm)", ylabel="paint height (µm)")
    for ax in (ax_x, ax_z, ax_h):
        ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    save_figure(fig, out)


def register(figs: argparse._SubParsersAction) -> None:
    p = figs.add_parser(
        "sides",
        help="the paint grid's slip walls against open sides: force and paint beside a drag",
        description=__doc__.split("\n\n", 1)[1],
    )
    p.add_argument("--out", required=True, type=Path, help="PNG file to write")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from paintapp.output_paths import prepare_outputs

    out: Path = args.out
    if out.suffix.lower() != ".png":
        raise InputError("the figure is written as PNG; give a .png file name", key="--out")
    prepare_outputs([("--out", out)])
    results = [drag(*case) for case in CASES]
    reference = results[-1].mean_force()
    for r in results:
        f, j = r.mean_force(), r.jitter()
        off = (f - reference) / np.abs(reference)
        print(
            f"{r.label:36s} drag {-f[0] * 1e3:6.2f} mN ({off[0] * -100:+5.1f} %)  "
            f"lift {f[2] * 1e3:6.2f} mN ({off[2] * 100:+5.1f} %)  sample-to-sample rms: "
            f"drag {j[0] * 1e3:.2f}, lift {j[2] * 1e3:.2f} mN  paint drift {r.drift:.1e}"
        )
    plot(results, out)
    print(f"wrote {out}")
    return 0
