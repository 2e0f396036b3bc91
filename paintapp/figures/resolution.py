"""``paintapp figures resolution --out F.png``: the paper's Fig. 5, for both boundary methods.

The same square-probe sweep at several grid resolutions (default 32, 64 and 128 cells per side),
coarsest in blue to finest in red, once with the paper's voxelized (``staircase``) probe and once
with cut cells (``cutcell``), side by side, and the relative force and torque noise
(:mod:`paintapp.bench.noise`) of both against the grid size: the staircase boundary's noise falls
as the grid is refined; the cut cells' is lower (64²: force 0.56 vs 0.66, torque 1.12 vs 2.98).
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from common.errors import InputError

if TYPE_CHECKING:  # the solver and scipy load only when a figure is made, not at CLI start-up
    from paintapp.figures._sweep_plot import SweepFigureData

DEFAULT_CELLS = (32, 64, 128)
METHODS = ("staircase", "cutcell")
TITLES = {"staircase": "staircase (voxelized probe)", "cutcell": "cut cells"}


def compute(
    cells: Sequence[int] = DEFAULT_CELLS, methods: Sequence[str] = METHODS
) -> list[SweepFigureData]:
    """One sweep per boundary method and grid size: methods in the given order, coarsest first."""
    from paintapp.figures._sweep_plot import check_cells, sweep_data

    sizes = sorted({check_cells(c) for c in cells})
    if len(sizes) < 2:
        raise InputError("expected at least two different grid sizes", key="--cells")
    bad = [m for m in methods if m not in METHODS]
    if bad or not methods:
        raise InputError(f"expected methods from {', '.join(METHODS)}, got {bad}", key="--methods")
    order = list(dict.fromkeys(methods))
    return [sweep_data(n, boundary_method=m) for m in order for n in sizes]


def noise_table(runs: Sequence[SweepFigureData]) -> list[tuple[str, int, float, float]]:
    """(boundary method, cells, force noise, torque noise) per run."""
    return [
        (r.boundary_method, r.cells, r.summary["force_noise"], r.summary["torque_noise"])
        for r in runs
    ]


def plot(runs: Sequence[SweepFigureData], out: str) -> None:
    """Draw the overlaid sweeps per method (one column each) and the noise against resolution."""
    import numpy as np
    from matplotlib.ticker import NullFormatter

    from paintapp.figures._sweep_plot import mark_phases, pyplot, save_figure

    methods = list(dict.fromkeys(r.boundary_method for r in runs))
    plt = pyplot()
    fig = plt.figure(figsize=(6.0 + 5.0 * len(methods), 10.0))
    grid = fig.add_gridspec(4, len(methods), height_ratios=[1, 1, 1, 0.9])
    labels = ["drag force (N/m)", "perpendicular force (N/m)", "torque (N m/m)"]
    first = None
    for col, method in enumerate(methods):
        mine = [r for r in runs if r.boundary_method == method]
        axes = []
        for row in range(3):
            share: dict[str, Any] = (
                {"sharex": first, "sharey": fig.axes[row] if col else None} if first else {}
            )
            axes.append(fig.add_subplot(grid[row, col], **share))
            first = first or axes[0]
        colours = plt.cm.jet(np.linspace(0.05, 0.95, len(mine)))  # coarsest blue, finest red
        for ax, label in zip(axes, labels, strict=True):
            mark_phases(ax)
            if col == 0:
                ax.set_ylabel(label)
        for r, c in zip(mine, colours, strict=True):
            t = r.trace.time_s
            name = f"{r.cells}x{r.cells}: noise {r.summary['force_noise']:.2f}"
            for ax, y in zip(axes, (r.drag, r.perpendicular, r.trace.torque), strict=True):
                ax.plot(t, y, color=c, lw=0.8, alpha=0.85, label=name)
        axes[0].set_title(TITLES.get(method, method), fontsize=10)
        axes[0].legend(fontsize=8, loc="lower left")
        for upper in axes[:2]:
            upper.tick_params(labelbottom=False)
        axes[2].set_xlabel("time (s)")
    ax = fig.add_subplot(grid[3, :])
    table = noise_table(runs)
    for method, style in zip(methods, ("o", "^", "v"), strict=False):
        rows = [row for row in table if row[0] == method]
        n = [row[1] for row in rows]
        name = TITLES.get(method, method)
        ax.plot(n, [row[2] for row in rows], style + "-", label=f"{name}: force noise")
        ax.plot(n, [row[3] for row in rows], style + "--", label=f"{name}: torque noise")
    sizes = sorted({row[1] for row in table})
    ax.set_xscale("log", base=2)
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xticks(sizes, [str(v) for v in sizes])
    ax.set_ylim(bottom=0.0)
    ax.set_xlabel("grid cells per side")
    ax.set_ylabel("relative noise")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    fig.suptitle(
        "Square probe sweep at several grid resolutions (paper Fig. 5): staircase vs cut cells",
        fontsize=11,
    )
    fig.tight_layout()
    save_figure(fig, out)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "resolution",
        help="paper Fig. 5: the sweep's noise against the grid, staircase vs cut cells",
    )
    p.add_argument("--out", required=True, metavar="F.png", help="PNG file to write")
    p.add_argument(
        "--cells",
        type=int,
        nargs="+",
        default=list(DEFAULT_CELLS),
        help="grid sizes, cells per side (default 32 64 128)",
    )
    p.add_argument(
        "--methods",
        nargs="+",
        choices=METHODS,
        default=list(METHODS),
        help="boundary methods, side by side (default staircase cutcell)",
    )
    p.set_defaults(func=_run)


def _run(args: argparse.Namespace) -> int:
    runs = compute(args.cells, args.methods)
    plot(runs, args.out)
    for method, cells, fn, tn in noise_table(runs):
        print(f"{method:<9} {cells:>4}x{cells:<4} force noise {fn:.3f}  torque noise {tn:.3f}")
    print(f"wrote {args.out}")
    return 0
