"""The servo loop's real-time check: run it on the real clock with the simulated device, idle and
beside a running 3D simulation, and collect the timing figures (``paintapp haptics-check``).

Each run takes one of the two forms the window can use: the loop in a thread of this process
(:func:`run_once`), or in a servo process of its own (:func:`run_process_once`, the window's
default) with the force samples crossing through shared memory; the process form also reports
what the OS granted it (priority, core, GC) and audits every device write. Every run reports the
share of the machine's CPU time the host took meanwhile (:mod:`~paintapp.bench.host_steal`).

Idle, a light thread stands in for the painting session and publishes a synthetic viscous drag
at 60 Hz. Under load, a thread steps the 3D scene ``sphere_stir_3d.toml`` as fast as it can and
publishes its probe's force after every step, as the session will; if the solver or the scene is
missing, a synthetic numpy workload of the same kind takes its place (and the output says so).
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np

from paintapp.bench.host_steal import StealMonitor, describe_steal
from paintapp.haptics.channel import ForceChannel, ForceSample
from paintapp.haptics.clock import RealTimeClock
from paintapp.haptics.devices.simulated import SimulatedDevice
from paintapp.haptics.process import ProcessOptions, ServoProcess
from paintapp.haptics.servo import ServoConfig, ServoLoop, ServoReport
from paintapp.haptics.synthetic import ViscousDragSource, run_source_thread

SimStep = Callable[[], ForceSample]
"""Advance the simulation one step; return the probe's force sample."""


@dataclass(frozen=True)
class CheckRun:
    """One run of the check.

    Attributes:
        label: "idle" or "beside 3D simulation".
        report: the servo loop's report (timing included).
        force_source: what published the force samples.
        samples_published: how many samples were published during the run.
        max_force_n: the largest force written to the device, N.
        granted: where the loop ran and what the OS granted it.
        bad_writes: non-finite or over-limit device writes (process form; None: not audited).
        host_steal, host_steal_peak: the share of the machine's CPU time the host took during
            the run (0-1), and its largest over any half second of it (None: unknown).
    """

    label: str
    report: ServoReport
    force_source: str
    samples_published: int
    max_force_n: float
    granted: str = "thread in this process"
    bad_writes: int | None = None
    host_steal: float | None = None
    host_steal_peak: float | None = None


def load_simulation() -> tuple[SimStep, str]:
    """The 3D scene as a step function and its description; a synthetic stand-in if unavailable."""
    try:
        from paintapp.resources import asset_path
        from solver import load_scene

        path = asset_path("scenes", "sphere_stir_3d.toml")
        scene = load_scene(path)
        sim = scene.build()
        probe = sim.probes[0].name
        sim.step(scene.run.dt_s)  # compile and warm up before anything is timed
    except Exception as exc:  # any failure: fall back, and say why
        return synthetic_workload(), f"synthetic 3D numpy workload ({exc})"
    dt_s = scene.run.dt_s
    cells = "x".join(str(c) for c in scene.grid.cells)

    def step() -> ForceSample:
        sim.step(dt_s)
        f = sim.forces[probe]
        return ForceSample(sim.time_s, f.force, np.broadcast_to(f.torque, (3,)))

    return step, f"3D simulation {path.name} ({cells} cells)"


def synthetic_workload(cells: int = 48, sweeps: int = 20) -> SimStep:
    """A numpy stand-in for a 3D fluid step: Jacobi sweeps of a 7-point stencil on a grid."""
    rng = np.random.default_rng(0)
    a = rng.random((cells, cells, cells))
    t = [0.0]

    def step() -> ForceSample:
        for _ in range(sweeps):
            a[1:-1, 1:-1, 1:-1] = (
                a[:-2, 1:-1, 1:-1]
                + a[2:, 1:-1, 1:-1]
                + a[1:-1, :-2, 1:-1]
                + a[1:-1, 2:, 1:-1]
                + a[1:-1, 1:-1, :-2]
                + a[1:-1, 1:-1, 2:]
            ) / 6.0
        t[0] += 0.01
        return ForceSample(t[0], np.array([0.01 * float(a[5, 5, 5]), 0.0, 0.0]), np.zeros(3))

    return step


@contextmanager
def _simulation_thread(step: SimStep, forces: ForceChannel) -> Iterator[list[int]]:
    count = [0]
    stop = threading.Event()

    def loop() -> None:
        while not stop.is_set():
            forces.publish(step())
            count[0] += 1

    thread = threading.Thread(target=loop, name="simulation", daemon=True)
    thread.start()
    try:
        yield count
    finally:
        stop.set()
        thread.join(30.0)


def run_once(
    seconds: float,
    config: ServoConfig,
    simulation: tuple[SimStep, str] | None = None,
    progress: Callable[[float], None] | None = None,
) -> CheckRun:
    """Run the real-time loop for ``seconds`` with the simulated device, optionally beside a
    simulation; ``progress`` is called with the elapsed seconds about ten times a second."""
    clock = RealTimeClock(config.tick_s)
    device = SimulatedDevice(clock.now_s)
    loop = ServoLoop(device, config=config)
    loop.open()
    try:
        with StealMonitor() as steal:
            if simulation is None:
                stop = threading.Event()
                source = ViscousDragSource(loop.states, loop.forces)
                thread = run_source_thread(source, 60.0, stop)
                _run_loop(loop, clock, seconds, progress)
                stop.set()
                thread.join(1.0)
                label, where, published = "idle", "synthetic drag, 60 Hz", source.published
            else:
                step, where = simulation
                forces = loop.forces
                with _simulation_thread(step, forces) as count:
                    _run_loop(loop, clock, seconds, progress)
                    published = count[0]
                label = "beside 3D simulation"
        report = loop.report()
    finally:
        loop.close()
    return CheckRun(
        label,
        report,
        where,
        published,
        device.max_force_written_n,
        host_steal=steal.share,
        host_steal_peak=steal.peak,
    )


def run_process_once(
    seconds: float,
    config: ServoConfig,
    simulation: tuple[SimStep, str] | None = None,
    progress: Callable[[float], None] | None = None,
    device: str = "sim:stroke",
) -> CheckRun:
    """Like :func:`run_once`, with the loop in a servo process of its own (the window's form):
    the simulation (or the synthetic drag) runs here and publishes through shared memory.
    ``device``: what the servo process drives (``--device``'s text; default the simulated
    stylus playing a stroke)."""
    servo = ServoProcess(ProcessOptions(device=device, config=config))
    servo.start()
    try:
        with StealMonitor() as steal:
            if simulation is None:
                stop = threading.Event()
                source = ViscousDragSource(servo.states, servo.forces)
                thread = run_source_thread(source, 60.0, stop)
                _wait(seconds, progress)
                stop.set()
                thread.join(1.0)
                label, where, published = "process, idle", "synthetic drag, 60 Hz", source.published
            else:
                step, where = simulation
                with _simulation_thread(step, servo.forces) as count:
                    _wait(seconds, progress)
                    published = count[0]
                label = "process, beside 3D"
    finally:
        report = servo.stop()
    if report is None:
        raise RuntimeError(f"the servo process ended without a report ({servo.fault})")
    audit = servo.audit()
    bad = int(audit.get("nonfinite_writes", 0) + audit.get("over_limit_writes", 0))
    max_force = float(audit.get("max_force_n", 0.0))
    return CheckRun(
        label, report, where, published, max_force, servo.granted, bad, steal.share, steal.peak
    )


def _wait(seconds: float, progress: Callable[[float], None] | None) -> None:
    start = time.perf_counter()
    while (elapsed := time.perf_counter() - start) < seconds:
        time.sleep(min(0.1, seconds - elapsed))
        if progress is not None:
            progress(min(time.perf_counter() - start, seconds))


def _run_loop(
    loop: ServoLoop, clock: RealTimeClock, seconds: float, progress: Callable[[float], None] | None
) -> None:
    start = time.perf_counter()
    loop.start(clock, seconds)
    while clock.running:
        time.sleep(0.1)
        if progress is not None:
            progress(min(time.perf_counter() - start, seconds))
    loop.stop()


def format_table(runs: list[CheckRun]) -> str:
    """The runs side by side, one row per figure."""
    rows: list[tuple[str, list[str]]] = [("", [r.label for r in runs])]
    rows.append(("force source", [r.force_source.split(" (")[0] for r in runs]))
    rows.append(("force samples published", [str(r.samples_published) for r in runs]))
    rows.append(("samples used by the loop", [str(r.report.fluid["fresh_samples"]) for r in runs]))
    timing = [r.report.timing for r in runs]
    for i, (name, _) in enumerate(timing[0].rows() if timing[0] else []):
        rows.append((name, [t.rows()[i][1] if t else "-" for t in timing]))
    rows.append(("max force written (N)", [f"{r.max_force_n:.3f}" for r in runs]))
    rows.append(("safety faults", [str(r.report.safety["faults"]) for r in runs]))
    rows.append(("device fault", [r.report.device_fault or "none" for r in runs]))
    rows.append(
        ("bad device writes", ["-" if r.bad_writes is None else str(r.bad_writes) for r in runs])
    )
    rows.append(("host CPU steal", [describe_steal(r.host_steal, r.host_steal_peak) for r in runs]))
    width = max(len(name) for name, _ in rows) + 2
    cols = [max(len(v[i]) for _, v in rows) + 2 for i in range(len(runs))]
    lines = [
        name.ljust(width) + "".join(v.rjust(c) for v, c in zip(vals, cols, strict=True))
        for name, vals in rows
    ]
    granted = sorted({r.granted for r in runs if r.granted != "thread in this process"})
    lines += [f"servo process: {g}" for g in granted]
    return "\n".join(lines)
