"""The bundled exploration example: Schäfer-Turek 2D-2 (Re 100, vortex shedding) computed by our
solver at D/h = 10: after the wake has started shedding, the shedding period is measured from the
cylinder's lift (upward zero crossings), then frames are written every 0.03 s over exactly one
period, which the file states (``period``) so that a replay can loop it seamlessly.

    python -m tests.support.flow_example assets/flows/schaefer_turek_2d2.npz
"""

from __future__ import annotations

import argparse
import copy
import sys
import tomllib
from pathlib import Path

from paintapp.explore.flow_export import FlowFrames, write_flow_npz
from paintapp.resources import asset_path
from solver.scenes.scene import parse_scene

#: Flow time before the period is measured (the wake is shedding by then), and frame interval.
SPIN_UP_S = 6.0
FRAME_DT_S = 0.03
#: Flow time over which the lift's zero crossings are collected.
MEASURE_S = 1.5


def example_scene(cells: tuple[int, int] = (220, 41), dt_s: float = 0.005):
    """The 2D-2 scene: the 2D-1 channel with a mean inflow of 1 m/s."""
    data = tomllib.loads(
        asset_path("scenes", "schaefer_turek_2d1.toml").read_text(encoding="utf-8")
    )
    data = copy.deepcopy(data)
    data["domain"]["cells"] = list(cells)
    data["boundary"]["x_min"]["velocity"] = [1.5, 0.0]
    data["run"] = {"dt": dt_s, "duration": SPIN_UP_S + MEASURE_S + 1.0}
    data.pop("output", None)
    data["name"] = "schaefer_turek_2d2"
    data["description"] = "Channel flow past a cylinder, Re = 100 (Schaefer & Turek 1996, 2D-2)"
    return parse_scene(data, "schaefer_turek_2d2")


def shedding_period(lift: list[float], dt_s: float) -> tuple[float, int]:
    """Mean period between upward zero crossings of the lift (about its mean), and the index of
    the last crossing."""
    import numpy as np

    q = np.asarray(lift) - float(np.mean(lift))
    ups = np.flatnonzero((q[:-1] < 0) & (q[1:] >= 0))
    if len(ups) < 3:
        raise RuntimeError("the wake is not shedding yet")
    return float(np.mean(np.diff(ups))) * dt_s, int(ups[-1])


def make_example(path: Path) -> None:
    scene = example_scene()
    sim = scene.build()
    dt = scene.run.dt_s
    for step in range(round(SPIN_UP_S / dt)):
        sim.step(dt)
        if step % 200 == 0:
            print(f"t = {sim.time_s:.2f} s", file=sys.stderr)
    lift = []
    for _ in range(round(MEASURE_S / dt)):
        sim.step(dt)
        lift.append(float(sim.forces["cylinder"].force[1]))
    period, last_up = shedding_period(lift, dt)
    # run on to the next upward crossing (one period after the last), then one period of frames
    for _ in range(round(period / dt) - (len(lift) - 1 - last_up)):
        sim.step(dt)
    frames = FlowFrames.start(sim)
    frames.period_s = period
    every = round(FRAME_DT_S / dt)
    for _ in range(int(period / (every * dt))):
        frames.add(sim)
        for _ in range(every):
            sim.step(dt)
    write_flow_npz(path, frames)
    print(f"wrote {path}: {len(frames.times_s)} frames over the shedding period {period:.4f} s")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Write the bundled exploration example.")
    parser.add_argument("out", type=Path)
    make_example(parser.parse_args(argv).out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
