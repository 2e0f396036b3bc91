"""The servo tick's own cost: back to back, and after a sleep as in the servo process.

    python benchmarks/bench_servo_tick.py [--ticks 3000] [--sleep-us 800] [--rounds 3]

Builds what the servo process runs (`paintapp/haptics/process.py`: the simulated device behind
the write audit, the servo loop on the shared-memory force and state channels), feeds it a force
sample every 16 ticks and moves the simulated hand's target, and times each tick on a virtual
clock: ``--ticks`` ticks back to back, then as many with ``--sleep-us`` of sleep after each (the
process sleeps to each deadline: a tick then starts on a core that idled, and on these virtual
machines costs several times as much). Then a replay's ticks: the demo's stroke file played
through :class:`paintapp.session.playback.ServoForcePath` on its virtual clock, record by record
as ``paintapp demo`` plays it, a force published every second sample in place of the painting.
Prints, per round, the median tick of the first two and the mean tick of the replay, in
microseconds.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from brushes import StylusSample
from paintapp.haptics.channel import ForceChannel
from paintapp.haptics.clock import VirtualClock
from paintapp.haptics.process import GatedDevice, ProcessOptions, build_device
from paintapp.haptics.servo import ServoLoop
from paintapp.haptics.shared_state import (
    SharedBlock,
    SharedForceChannel,
    SharedStateChannel,
    SharedTarget,
)
from paintapp.resources import asset_path
from paintapp.session.playback import ServoForcePath
from paintapp.strokes.files import StrokeFile, read_strokes


def _positive(text: str) -> int:
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text}")
    return value


def _sleep_us(text: str) -> float:
    value = float(text)
    if not 0.0 <= value <= 1e5:
        raise argparse.ArgumentTypeError(f"expected microseconds in [0, 100000], got {text}")
    return value


class TickBench:
    """The servo process's tick, on a virtual clock (see the module docstring)."""

    def __init__(self) -> None:
        options = ProcessOptions()
        config = options.config
        self.block = SharedBlock()
        self.clock = VirtualClock(config.tick_s)
        self.target = SharedTarget(self.block.target, options.start_m)
        raw = build_device("sim", self.clock.now_s, self.target)
        device = GatedDevice(raw, self.block.audit, config.tick_s / options.exit_fade_s)
        self.forces = SharedForceChannel(self.block.force)
        self.loop = ServoLoop(device, self.forces, config, SharedStateChannel(self.block.state))
        self.loop.open()
        self.rng = np.random.default_rng(0)
        self.index = 0

    def run(self, ticks: int, sleep_s: float) -> float:
        """Median tick, us, over ``ticks`` ticks with ``sleep_s`` after each."""
        costs = []
        for _ in range(ticks):
            i = self.index
            self.index += 1
            t = i * 1e-3
            self.clock._now_s = t  # the virtual clock's time, advanced by hand
            if i % 16 == 0:
                f, m = self.rng.normal(size=3) * 0.3, self.rng.normal(size=3) * 0.01
                self.forces.publish_force(t, f, m)
            if i % 50 == 0:
                depth = 0.0005 + 0.002 * (i % 400) / 400
                self.target.set_position((0.01 * np.sin(i / 500), 0.02, -depth))
            begin = time.perf_counter()
            self.loop._guarded_tick(i, t)
            costs.append(time.perf_counter() - begin)
            if sleep_s:
                time.sleep(sleep_s)
        return 1e6 * statistics.median(costs)

    def close(self) -> None:
        self.loop.close()
        self.block.close()


def replay_tick_us(strokes: StrokeFile) -> float:
    """Mean tick, us, of the replay's force path over ``strokes`` (see the module docstring)."""
    channel = ForceChannel()
    path = ServoForcePath(strokes.samples, channel, source=strokes.source)
    records = strokes.records
    begin = time.perf_counter()
    for i, record in enumerate(records):
        if isinstance(record, StylusSample):
            if i % 2 == 0:
                channel.publish_force(record.t_s, (0.01 * (i % 7), 0.02, -0.1), (0.0, 1e-4, 0.0))
            path.run_until(records[i + 1].t_s if i + 1 < len(records) else None)
    seconds = time.perf_counter() - begin
    path.close()
    return 1e6 * seconds / max(path.ticks, 1)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--ticks", type=_positive, default=3000)
    parser.add_argument("--sleep-us", type=_sleep_us, default=800.0)
    parser.add_argument("--rounds", type=_positive, default=3)
    args = parser.parse_args()
    bench = TickBench()
    strokes = read_strokes(asset_path("strokes", "demo.jsonl"))
    try:
        bench.run(1000, 0.0)  # first calls into numpy and the device
        replay_tick_us(strokes)
        print("round  back to back (us)  after a sleep (us)  a replay's (us)")
        for r in range(args.rounds):
            warm = bench.run(args.ticks, 0.0)
            cold = bench.run(args.ticks, 1e-6 * args.sleep_us)
            replay = replay_tick_us(strokes)
            print(f"{r + 1:5d}  {warm:17.1f}  {cold:18.1f}  {replay:15.1f}", flush=True)
    finally:
        bench.close()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
