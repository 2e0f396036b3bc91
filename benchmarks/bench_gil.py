"""How much the painting step slows down beside a thread that holds the interpreter lock.

In the painting window the simulation worker shares the interpreter lock with the GUI thread. This
benchmark isolates that effect from the window's other costs: it steps the window's default scene
(the canvas, brush and one-thread scene of ``bench_painting.py``'s window row) headless, in
alternating rounds without and with a second thread that runs Python (and so holds the lock) for
``--burst-ms`` and then sleeps for ``--period-ms``, as a GUI thread does while it handles a frame,
and prints both paint-step rates and their ratio.

    python benchmarks/bench_gil.py [--burst-ms 1] [--period-ms 8] [--rounds 4] [--steps 60]

The worker calls a kernel (which releases the lock) about 70 times a paint step, and needs the
lock back after each one: so it waits for most of every burst, whatever the length of its
kernels.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import threading
import time
from pathlib import Path

from tqdm import tqdm

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_painting import PIGMENTS, window_case

from paintapp.session.painting import PaintingSession

# the synthetic stroke generator is test tooling (tests/support), beside this script's folder
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from tests.support.demo_strokes import StrokeSpec, stroke_samples

WARMUP_STEPS = 6


class LockHolder(threading.Thread):
    """Runs Python for ``burst_s`` (holding the interpreter lock), then sleeps ``period_s``, while
    :attr:`busy` is set."""

    def __init__(self, burst_s: float, period_s: float) -> None:
        super().__init__(daemon=True, name="lock-holder")
        self.burst_s, self.period_s = burst_s, period_s
        self.busy = threading.Event()
        self.stop = threading.Event()
        self.held_s = 0.0

    def run(self) -> None:
        while not self.stop.is_set():
            if self.busy.is_set():
                start = time.perf_counter()
                while time.perf_counter() - start < self.burst_s:
                    pass
                self.held_s += time.perf_counter() - start
            time.sleep(self.period_s)


def steps_per_second(steps: int) -> float:
    """Paint steps per second of the window's scene over ``steps`` samples of a straight
    stroke (after a few that load the brush into the paint)."""
    canvas, preset, scene = window_case()
    session = PaintingSession(canvas, preset, scene)
    session.load_pigment(PIGMENTS[0], 1e-8)
    size = canvas.size_m[0]
    spec = StrokeSpec((0.3 * size, 0.5 * size), (0.7 * size, 0.52 * size),
                      (steps + WARMUP_STEPS + 4) / 60.0, 0.8, (0.2, 0.0))  # fmt: skip
    samples = list(stroke_samples(spec, 0.0))
    for sample in samples[:WARMUP_STEPS]:
        session.sample(sample)
    start, painted = time.perf_counter(), 0
    for sample in samples[WARMUP_STEPS : WARMUP_STEPS + steps]:
        painted += session.sample(sample).paint is not None
    return painted / (time.perf_counter() - start)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--burst-ms", type=float, default=1.0,
                        help="how long the second thread holds the lock each time")  # fmt: skip
    parser.add_argument("--period-ms", type=float, default=8.0,
                        help="how long it sleeps between bursts")  # fmt: skip
    parser.add_argument("--rounds", type=int, default=4)
    parser.add_argument("--steps", type=int, default=60, help="timed paint steps per run")
    args = parser.parse_args(argv)
    finite = all(math.isfinite(v) and v > 0 for v in (args.burst_ms, args.period_ms))
    if not finite or args.rounds < 1 or args.steps < 1:
        parser.error("--burst-ms and --period-ms must be positive and finite, --rounds and "
                     "--steps at least 1")  # fmt: skip
    steps_per_second(2)  # loads the kernels
    holder = LockHolder(1e-3 * args.burst_ms, 1e-3 * args.period_ms)
    holder.start()
    rates: dict[bool, list[float]] = {False: [], True: []}
    busy_s = 0.0
    order = ((False, True), (True, False))  # alternate which goes first
    runs = [busy for r in range(args.rounds) for busy in order[r % 2]]
    for busy in tqdm(runs, desc="runs", leave=False, file=sys.stderr, disable=None):
        (holder.busy.set if busy else holder.busy.clear)()
        start = time.perf_counter()
        rates[busy].append(steps_per_second(args.steps))
        if busy:
            busy_s += time.perf_counter() - start
    holder.stop.set()
    alone, beside = statistics.median(rates[False]), statistics.median(rates[True])
    share = holder.held_s / busy_s if busy_s > 0 else 0.0
    print(f"window scene, {args.steps} paint steps a run, {args.rounds} alternating rounds")
    print(f"alone:                      {alone:.1f} paint steps/s "
          f"({', '.join(f'{r:.1f}' for r in rates[False])})")  # fmt: skip
    print(f"beside the lock holder:     {beside:.1f} paint steps/s "
          f"({', '.join(f'{r:.1f}' for r in rates[True])})")  # fmt: skip
    print(f"lock held by the other thread {share:.0%} of the time ({args.burst_ms:g} ms bursts, "
          f"{args.period_ms:g} ms apart); rate beside it {beside / alone:.0%} of the rate alone")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
