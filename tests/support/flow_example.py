"""The bundled exploration example: Schäfer-Turek 2D-2 (Re 100, vortex shedding) computed by our
solver at D/h = 10, a dozen frames over about one shedding period.

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
from solver.scene import parse_scene

#: Flow time before the frames (the wake is shedding by then), frame interval and count.
SPIN_UP_S = 6.0
FRAME_DT_S = 0.03
FRAMES = 12


def example_scene(cells: tuple[int, int] = (220, 41), dt_s: float = 0.005):
    """The 2D-2 scene: the 2D-1 channel with a mean inflow of 1 m/s."""
    data = tomllib.loads(
        asset_path("scenes", "schaefer_turek_2d1.toml").read_text(encoding="utf-8")
    )
    data = copy.deepcopy(data)
    data["domain"]["cells"] = list(cells)
    data["boundary"]["x_min"]["velocity"] = [1.5, 0.0]
    data["run"] = {"dt": dt_s, "duration": SPIN_UP_S + FRAME_DT_S * FRAMES}
    data.pop("output", None)
    data["name"] = "schaefer_turek_2d2"
    data["description"] = "Channel flow past a cylinder, Re = 100 (Schaefer & Turek 1996, 2D-2)"
    return parse_scene(data, "schaefer_turek_2d2")


def make_example(path: Path) -> None:
    scene = example_scene()
    sim = scene.build()
    dt = scene.run.dt_s
    frames = FlowFrames.start(sim)
    steps_per_frame = round(FRAME_DT_S / dt)
    spin_up = round(SPIN_UP_S / dt)
    for step in range(spin_up + steps_per_frame * FRAMES):
        sim.step(dt)
        if step >= spin_up and (step - spin_up + 1) % steps_per_frame == 0:
            frames.add(sim)
        if step % 200 == 0:
            print(f"t = {sim.time_s:.2f} s", file=sys.stderr)
    write_flow_npz(path, frames)
    print(f"wrote {path}: {len(frames.times_s)} frames")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Write the bundled exploration example.")
    parser.add_argument("out", type=Path)
    make_example(parser.parse_args(argv).out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
