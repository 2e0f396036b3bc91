"""``paintapp figures resolution --out F.png``: the paper's Fig. 5.

The same square-probe sweep at several grid resolutions (default 32, 64 and 128 cells per side),
coarsest in blue to finest in red, and the relative force and torque noise
(:mod:`paintapp.bench.noise`) against the grid size: the staircase boundary's noise falls as the
grid is refined.
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from typing import TYPE_CHECKING

from common.errors import InputError

if TYPE_CHECKING:  # the solver and scipy load only when a figure is made, not at CLI start-up
    from paintapp.figures._sweep_plot import SweepFigureData

DEFAULT_CELLS = (32, 64, 128)


def compute(cells: Sequence[int] = DEFAULT_CELLS) -> list[SweepFigureData]:
    """One sweep per grid size, coarsest first."""
    from paintapp.figures._sweep_plot import check_cells, sweep_data

    sizes = sorted({check_cells(c) for c in cells})
    if len(sizes) < 2:
        raise InputError("expected at least two different grid sizes", key="--cells")
    return [sweep_data(n) for n in sizes]


def noise_table(runs: Sequence[SweepFigureData]) -> list[tuple[int, float, float]]:
    """(cells, force noise, torque noise) per run."""
    return [(r.cells, r.summary["force_noise"], r.summary["torque_noise"]) for r in runs]


def plot(runs: Sequence[SweepFigureData], out: str) -> None:
    """Draw the overlaid sweeps and the noise against resolution; write ``out`` (PNG)."""
    import numpy as np
    from matplotlib.ticker import NullFormatter

    from paintapp.figures._sweep_plot import mark_phases, pyplot, save_figure

    plt = pyplot()
    fig = plt.figure(figsize=(8.5, 10.0))
    grid = fig.add_gridspec(4, 1, height_ratios=[1, 1, 1, 0.9])
    axes = [fig.add_subplot(grid[0])]
    axes += [fig.add_subplot(grid[i], sharex=axes[0]) for i in (1, 2)]
    colours = plt.cm.jet(np.linspace(0.05, 0.95, len(runs)))  # coarsest blue, finest red
    labels = ["drag force (N/m)", "perpendicular force (N/m)", "torque (N m/m)"]
    for ax, label in zip(axes, labels, strict=True):
        mark_phases(ax)
        ax.set_ylabel(label)
    for r, c in zip(runs, colours, strict=True):
        t = r.trace.time_s
        name = f"{r.cells}x{r.cells}: noise {r.summary['force_noise']:.2f}"
        for ax, y in zip(axes, (r.drag, r.perpendicular, r.trace.torque), strict=True):
            ax.plot(t, y, color=c, lw=0.8, alpha=0.85, label=name)
    axes[0].legend(fontsize=8, loc="lower left")
    for upper in axes[:2]:
        upper.tick_params(labelbottom=False)
    axes[2].set_xlabel("time (s)")
    ax = fig.add_subplot(grid[3])
    table = noise_table(runs)
    n = [row[0] for row in table]
    ax.plot(n, [row[1] for row in table], "o-", label="force noise")
    ax.plot(n, [row[2] for row in table], "s--", label="torque noise")
    ax.set_xscale("log", base=2)
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xticks(n, [str(v) for v in n])
    ax.set_ylim(bottom=0.0)
    ax.set_xlabel("grid cells per side")
    ax.set_ylabel("relative noise")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    fig.suptitle("Square probe sweep at several grid resolutions (paper Fig. 5)", fontsize=11)
    fig.tight_layout()
    save_figure(fig, out)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "resolution", help="paper Fig. 5: the sweep's noise falls as the grid is refined"
    )
    p.add_argument("--out", required=True, metavar="F.png", help="PNG file to write")
    p.add_argument(
        "--cells", type=int, nargs="+", default=list(DEFAULT_CELLS),
        help="grid sizes, cells per side (default 32 64 128)",
    )  # fmt: skip
    p.set_defaults(func=_run)


def _run(args: argparse.Namespace) -> int:
    runs = compute(args.cells)
    plot(runs, args.out)
    for cells, fn, tn in noise_table(runs):
        print(f"{cells:>4}x{cells:<4} force noise {fn:.3f}  torque noise {tn:.3f}")
    print(f"wrote {args.out}")
    return 0
