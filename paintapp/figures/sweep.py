"""``paintapp figures sweep --out F.png``: the paper's Fig. 4.

The forces on a square probe swept along an arc while it spins, then back along the same path
(``assets/scenes/paper_square_sweep.toml``): the drag force (the component along the motion;
negative means it opposes the motion), the component perpendicular to the motion, and the torque,
unfiltered as the paper shows them, with a smoothed line over each and the probe's speed and spin
for comparison.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # the solver and scipy load only when a figure is made, not at CLI start-up
    from paintapp.figures._sweep_plot import SweepFigureData


def compute(cells: int = 64, force_model: str = "stress") -> SweepFigureData:
    """The data of the figure: one sweep at ``cells`` per side (the paper: 64)."""
    from paintapp.figures._sweep_plot import sweep_data

    return sweep_data(cells, force_model)


def plot(data: SweepFigureData, out: str) -> None:
    """Draw the three panels and write them to ``out`` (PNG)."""
    import numpy as np

    from paintapp.bench.noise import smooth
    from paintapp.figures._sweep_plot import mark_phases, pyplot, save_figure

    plt = pyplot()
    tr = data.trace
    t = tr.time_s
    fig, axes = plt.subplots(3, 1, figsize=(8.0, 8.5), sharex=True)
    rows = [
        (
            data.drag,
            "drag force (N/m)\nalong the motion",
            np.linalg.norm(tr.velocity, axis=1),
            "speed (m/s)",
        ),
        (data.perpendicular, "perpendicular force (N/m)", None, None),
        (tr.torque, "torque (N m/m)", tr.omega, "spin (rad/s)"),
    ]
    for ax, (y, label, motion, motion_label) in zip(axes, rows, strict=True):
        mark_phases(ax)
        ax.plot(t, y, color="tab:blue", lw=0.7, label="unfiltered")
        ok = np.isfinite(y)
        ax.plot(t[ok], smooth(y[ok], tr.dt_s), color="navy", lw=1.6, label="smoothed (0.1 s)")
        ax.set_ylabel(label)
        if motion is not None:
            twin = ax.twinx()
            twin.plot(t, motion, color="0.45", ls=":", lw=1.2)
            twin.set_ylabel(motion_label, color="0.45")
    axes[0].legend(loc="lower left", fontsize=8)
    axes[-1].set_xlabel("time (s): out along the arc 0-1 s, back 1-2 s, at rest after")
    s = data.summary
    fig.suptitle(
        f"Square probe sweep, {data.cells}x{data.cells} grid (paper Fig. 4)\n"
        f"noise: force {s['force_noise']:.2f}, torque {s['torque_noise']:.2f}; "
        f"corr(F, v) = {s['force_velocity_corr']:.2f}, "
        f"corr(torque, spin) = {s['torque_spin_corr']:.2f}",
        fontsize=10,
    )
    fig.tight_layout()
    save_figure(fig, out)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("sweep", help="paper Fig. 4: drag, perpendicular force, torque on a sweep")
    p.add_argument("--out", required=True, metavar="F.png", help="PNG file to write")
    p.add_argument("--cells", type=int, default=64, help="grid cells per side (default 64)")
    p.add_argument(
        "--force-model",
        default="stress",
        choices=["stress", "control_volume"],
        help="force model (default: the paper's stress integral)",
    )
    p.set_defaults(func=_run)


def _run(args: argparse.Namespace) -> int:
    data = compute(args.cells, args.force_model)
    plot(data, args.out)
    s = data.summary
    print(
        f"sweep at {data.cells}x{data.cells}: force noise {s['force_noise']:.3f}, torque noise "
        f"{s['torque_noise']:.3f}, corr(F, v) {s['force_velocity_corr']:.2f}, "
        f"corr(torque, spin) {s['torque_spin_corr']:.2f}"
    )
    print(f"wrote {args.out}")
    return 0
