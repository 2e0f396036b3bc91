"""``paintapp haptics-check [--seconds S] [--form thread|process|both] [--device NAME[:ARG]]``: how
well the 1 kHz servo loop keeps time.

Runs the real-time servo loop with the simulated device for S seconds idle, then S seconds beside
a running 3D simulation, in a thread of this process and in a servo process of its own (the
window's form), and prints achieved rate, lateness percentiles, missed deadlines and the cost of a
tick side by side, and what the OS granted the servo process. With the process form it then runs
the machine's own floor for S seconds (the same clock, priority and core with an empty tick:
:mod:`paintapp.haptics.bare_loop`), the lateness no servo loop on this machine can beat.

``--device openhaptics[:NAME]|dhd|haply[:ID]`` runs the same check on a vendor device instead
(idle, with the synthetic drag): every write is audited (non-finite, over the device's limit)
and the device is closed with zero force at the end.
"""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING

from common.errors import InputError
from paintapp.haptics.device import DeviceNotFoundError

if TYPE_CHECKING:
    from paintapp.bench.servo_check import CheckRun
    from paintapp.haptics.servo import ServoConfig


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
        "--device",
        default="sim",
        metavar="sim|openhaptics[:NAME]|dhd|haply[:ID]",
        help="the device to run (default: the simulated stylus)",
    )
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


def _vendor_thread_run(text: str, seconds: float, config: ServoConfig) -> CheckRun:
    """The loop in a thread of this process with the device ``text`` names, idle, every write
    audited."""
    import threading
    import time

    import numpy as np

    from paintapp.bench.servo_check import CheckRun
    from paintapp.haptics.clock import RealTimeClock
    from paintapp.haptics.process import GatedDevice, build_device
    from paintapp.haptics.servo import ServoLoop
    from paintapp.haptics.shared_state import AUDIT_WIDTH
    from paintapp.haptics.synthetic import ViscousDragSource, run_source_thread

    clock = RealTimeClock(config.tick_s)
    audit = np.zeros(AUDIT_WIDTH)
    device = GatedDevice(build_device(text, clock.now_s, None), audit, 0.0)
    loop = ServoLoop(device, config=config)
    loop.open()
    try:
        stop = threading.Event()
        source = ViscousDragSource(loop.states, loop.forces)
        thread = run_source_thread(source, 60.0, stop)
        loop.start(clock, seconds)
        while clock.running:
            time.sleep(0.05)
        loop.stop()
        stop.set()
        thread.join(1.0)
        report = loop.report()
    finally:
        loop.close()
    bad = int(audit[1] + audit[2])
    return CheckRun(
        "idle", report, "synthetic drag, 60 Hz", source.published, float(audit[3]), bad_writes=bad
    )


def _vendor_process_run(text: str, seconds: float, config: ServoConfig) -> CheckRun:
    """The loop in a servo process of its own with the device ``text`` names, idle."""
    from paintapp.bench.servo_check import run_process_once

    return run_process_once(seconds, config, device=text)


def run_vendor(args: argparse.Namespace, config: ServoConfig, forms: list[str]) -> list[CheckRun]:
    """The check on a vendor device: one idle run per form."""
    from dataclasses import replace

    from paintapp.haptics.devices.backends import split_device

    try:
        if split_device(args.device) is None:
            raise InputError(f"unknown --device {args.device!r}", key="--device")
    except DeviceNotFoundError as exc:
        raise InputError(str(exc), key="--device") from exc
    print(
        f"haptics-check: {args.device}, servo {' and '.join(forms)} at "
        f"{1 / config.tick_s:.0f} Hz, {args.filter} filter, force scale {args.scale:g}, "
        f"{args.seconds:g} s per run, idle (synthetic drag)"
    )
    runs = []
    for form in forms:
        if form == "thread":
            runs.append(_vendor_thread_run(args.device, args.seconds, config))
        else:
            quiet = replace(config, record=False)
            runs.append(_vendor_process_run(args.device, args.seconds, quiet))
    return runs


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
    forms = ["thread", "process"] if args.form == "both" else [args.form]
    if args.device != "sim":
        runs = run_vendor(args, config, forms)
        print(format_table(runs))
        for r in runs:
            if r.report.device_fault is not None:
                print(f"{r.label}: the device stopped the loop: {r.report.device_fault}")
        _print_verdict(runs, forms)
        return 0
    simulation = None if args.idle_only else load_simulation()
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
    _print_verdict(runs, forms)
    return 0


def _print_verdict(runs: list[CheckRun], forms: list[str]) -> None:
    verdicts = []
    for form in forms:
        timings = [
            r.report.timing
            for r in runs
            if r.report.timing is not None and r.label.startswith("process") == (form == "process")
        ]
        worst = max((t.missed_deadlines / max(t.ticks, 1) for t in timings), default=1.0)
        late = "late: more than 2 % of the scheduled ticks were missed"
        verdicts.append(f"{form} {'ok' if worst < 0.02 else late}")
    print(f"verdict: {'; '.join(verdicts)}")
