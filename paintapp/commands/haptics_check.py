"""``paintapp haptics-check [--seconds S] [--form thread|process|both]``: how well the 1 kHz servo
loop keeps time.

Runs the real-time servo loop with the simulated device for S seconds idle, then S seconds beside
a running 3D simulation, in a thread of this process and in a servo process of its own (the
window's form), and prints achieved rate, lateness percentiles, missed deadlines and the cost of a
tick side by side, and what the OS granted the servo process. With the process form it then runs
the machine's own floor for S seconds (the same clock, priority and core with an empty tick:
:mod:`paintapp.haptics.bare_loop`), the lateness no servo loop on this machine can beat.
"""

from __future__ import annotations

import argparse
import sys

from common.errors import InputError


def register(sub: argparse._SubParsersAction) -> None:
    from paintapp.haptics.filters import FILTER_KINDS

    p = sub.add_parser(
        "haptics-check",
        help="run the 1 kHz haptic servo loop (simulated device) idle and under load; print timing",
    )
    p.add_argument("--seconds", type=float, default=3.0, help="length of each run (default 3)")
    p.add_argument("--scale", type=float, default=4.0, help="fluid force scale (default 4)")
    p.add_argument("--filter", choices=FILTER_KINDS, default="fir", help="reconstruction filter")
    p.add_argument("--idle-only", action="store_true", help="skip the run beside the simulation")
    p.add_argument(
        "--form",
        choices=("thread", "process", "both"),
        default="both",
        help="run the loop in a thread, in its own process (the window's form), or both (default)",
    )
    p.set_defaults(func=run)


def bare_floor(seconds: float) -> str:
    """One line: the machine's own timing floor (:mod:`paintapp.haptics.bare_loop`)."""
    from paintapp.haptics.bare_loop import measure_bare_loop

    try:
        return f"machine floor: {measure_bare_loop(seconds).describe()}"
    except RuntimeError as exc:
        return f"machine floor: not measured ({exc})"


def run(args: argparse.Namespace) -> int:
    from dataclasses import replace

    from tqdm import tqdm

    from paintapp.bench.servo_check import (
        format_table,
        load_simulation,
        run_once,
        run_process_once,
    )
    from paintapp.haptics.filters import FilterConfig
    from paintapp.haptics.fluid import FluidConfig
    from paintapp.haptics.servo import ServoConfig

    if not 0.1 <= args.seconds <= 600:
        raise InputError(f"--seconds must be between 0.1 and 600, got {args.seconds}")
    config = ServoConfig(
        filter=FilterConfig(kind=args.filter), fluid=FluidConfig(force_scale=args.scale)
    )
    simulation = None if args.idle_only else load_simulation()
    forms = ["thread", "process"] if args.form == "both" else [args.form]
    print(
        f"haptics-check: simulated 6-DOF stylus, servo {' and '.join(forms)} at "
        f"{1 / config.tick_s:.0f} Hz, "
        f"{args.filter} filter, force scale {args.scale:g}, {args.seconds:g} s per run"
    )
    if simulation is not None:
        print(f"load: {simulation[1]}")
    runs = []
    plan = [(f, s) for f in forms for s in ([None] if simulation is None else [None, simulation])]
    for form, sim in plan:
        label = "idle" if sim is None else "beside 3D simulation"
        label = label if form == "thread" else f"process, {label}"
        with tqdm(
            total=args.seconds,
            desc=label,
            unit="s",
            file=sys.stderr,
            disable=None,
            leave=False,
            bar_format="{desc}: {n:.1f}/{total:.1f} s",
        ) as bar:

            def progress(elapsed: float, bar: tqdm = bar) -> None:
                bar.n = elapsed
                bar.refresh()

            if form == "thread":
                runs.append(run_once(args.seconds, config, sim, progress))
            else:
                quiet = replace(config, record=False)  # the child keeps no tick log
                runs.append(run_process_once(args.seconds, quiet, sim, progress))
    print(format_table(runs))
    if "process" in forms:
        print(bare_floor(args.seconds))
    verdicts = []
    for form in forms:
        timings = [
            r.report.timing
            for r in runs
            if r.report.timing is not None and r.label.startswith("process") == (form == "process")
        ]
        worst = max(t.missed_deadlines / max(t.ticks, 1) for t in timings)
        late = "late: more than 2 % of the scheduled ticks were missed"
        verdicts.append(f"{form} {'ok' if worst < 0.02 else late}")
    print(f"verdict: {'; '.join(verdicts)}")
    return 0
