"""Frame rate, simulation rate and servo jitter of the painting window while it paints.

    python benchmarks/bench_app.py [--seconds 6] [--device none|sim|openhaptics|dhd|haply] [--servo process|thread]
                                   [--simulation thread|process]
                                   [--headless-seconds S] [--bare-seconds S] [--rounds N]
                                   [--json OUT.json]
                                   [--screenshot OUT.png]
                                   [--zoom fit,100,800]

Opens the real window (on the current display, or on a private Xvfb server when there is none),
dips the brush, and paints a synthesized circular stroke for ``--seconds``, its pressure rising
over its first 0.2 s: as tablet events sent to the canvas widget (``none``), or as the simulated
hand's target (``sim``: the hand first carried to the stroke's start in the air, untimed; it also
runs the 1 kHz servo loop, in its own process unless ``--servo thread``), with the window's
simulation in a thread of the window or (``--simulation process``) a process of its own. Prints
the display frame rate (passes of the render loop, each leaving the screen up to date, and how
many of them had something to redraw), the paint steps per second, and with a device the servo loop's achieved
rate, tick-interval jitter and start lateness, and what the OS granted the servo process. Then
(unless ``--headless-seconds 0``) it feeds the very samples and events the window's simulation
consumed (its journal) to a fresh session of the same brush and scene -- no window, no servo loop
-- as fast as it takes them, from the first paint step on, and prints that paint-step rate, the
window's share of it, the replay's real-time ratio (wall seconds per second of the journal),
and the edge width of the paint it left (:mod:`paintapp.canvas.edges`, global and local).

``--rounds N`` repeats the whole measurement N times (a fresh window and servo process each time,
each window run followed by its own headless run) and ends with a table of every round and the
medians. The machines are shared and their speed drifts by tens of percent within minutes: the
window's share of the headless rate is only meaningful between a window run and the headless run
right after it, and its median over rounds says more than any one pair. The share is the
product of two figures the table shows: the CPU time the worker thread got per second of the
window run (the headless run's is about 1.0; less is time spent waiting, for the interpreter
lock or a core), times the headless run's CPU time per paint step over the window's (more in
the window is the same work slowed by the caches and cores it shares with the GUI, the
rasterizer and the servo process). The row of the servo's median tick cost (the same work every
tick) shows how fast the machine ran during each round's window run. Three more rows give the
share of the machine's CPU time that the host took during each round's window run (over the
run, and its largest over any half second) and its headless run (Linux's steal counter; on a
virtual machine, time in which its CPUs had work but the hypervisor ran something else): a
round with steal is a round in which the host, not the program, set part of the figures.
With a device, each round ends with the machine's own floor (unless ``--bare-seconds 0``): the
servo process's clock, priority and core with an empty tick, alone for ``--bare-seconds``
(default ``--seconds``) on the idle machine (:mod:`paintapp.haptics.bare_loop`); a servo stall
that the bare loop shows as well is the machine's, not the loop's.
``--zoom`` paints at each of the given views in turn, in the same window, for ``--seconds`` each
(a comma-separated list or the option repeated; ``fit`` fits the canvas to the window, a number
is a zoom in percent, 100 showing one canvas texel per device pixel, within 5-1600): it prints
the frame rate, the frames with changes and the simulation rate at each, and keeps them as
``frame rate at Z``, ``frames with changes at Z`` and ``simulation rate at Z``. The stroke is
centred in the view: at ``fit`` the circle above; zoomed in, a circle of 0.3 times the smaller
side of the canvas area in sight (at most the quarter of the canvas height), so that the paint
stays on screen; the brush is loaded afresh for each view. The round's other figures (and the
headless run, which replays the journal from its start) are those of the first view; the
servo's cover the whole run. Without ``--zoom`` the canvas is fitted (``fit``).
``--json`` writes every figure to a file as well (the medians at the top level, each round's
figures under ``"rounds"``).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np


def private_display() -> subprocess.Popen | None:
    """Start Xvfb when no display is set; returns the process (None if a display exists)."""
    if os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"):
        return None
    if shutil.which("Xvfb") is None:
        sys.exit("no display and no Xvfb to start one")
    read_fd, write_fd = os.pipe()
    proc = subprocess.Popen(
        ["Xvfb", "-displayfd", str(write_fd), "-screen", "0", "1600x1000x24", "-nolisten", "tcp"],
        pass_fds=(write_fd,),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    os.close(write_fd)
    with os.fdopen(read_fd) as pipe:
        os.environ["DISPLAY"] = ":" + pipe.readline().strip()
    return proc


def tablet_sender(widget):
    """A function sending one synthesized QTabletEvent to ``widget``."""
    from PySide6.QtCore import QPointF, Qt
    from PySide6.QtGui import QInputDevice, QPointingDevice, QTabletEvent
    from PySide6.QtWidgets import QApplication

    caps = QInputDevice.Capability
    device = QPointingDevice(
        "bench stylus", 1, QInputDevice.DeviceType.Stylus, QPointingDevice.PointerType.Pen,
        caps.Position | caps.Pressure | caps.XTilt | caps.YTilt, 1, 3,
    )  # fmt: skip

    def send(kind, x: float, y: float, pressure: float) -> None:
        pos = QPointF(x, y)
        event = QTabletEvent(
            kind, device, pos, widget.mapToGlobal(pos), pressure, 15.0, 0.0, 0.0, 0.0, 0.0,
            Qt.KeyboardModifier.NoModifier, Qt.MouseButton.LeftButton, Qt.MouseButton.LeftButton,
        )  # fmt: skip
        QApplication.sendEvent(widget, event)

    send.device = device  # keep the device alive with the sender
    return send


#: Seconds the simulated hand is given to reach the stroke's start in the air before the timing
#: (its grip's spring rings down to under a millimetre of a 0.25 m move), and the seconds over
#: which the pen's pressure then rises to ``PRESSURE``: a brush set down, not dropped.
APPROACH_S = 1.0
PRESS_S = 0.2
PRESSURE = 0.8


def circle_m(win, t: float, radius_m: float | None = None) -> tuple[float, float]:
    """The stroke: a circle about the canvas centre, once per 3 s, of radius ``radius_m``
    (default a quarter of the canvas height)."""
    w, h = win.shared.canvas.size_m
    r = 0.25 * h if radius_m is None else radius_m
    a = 2.0 * math.pi * t / 3.0
    return 0.5 * w + r * math.cos(a), 0.5 * h + r * math.sin(a)


def parse_zooms(values: list[str] | None) -> list[str]:
    """The ``--zoom`` views: ``fit`` or a zoom in percent (5-1600), in order; default fit."""
    zooms: list[str] = []
    for value in values or ["fit"]:
        for part in value.split(","):
            part = part.strip().lower().removesuffix("%").strip()
            if not part:
                continue
            if part != "fit":
                try:
                    percent = float(part)
                except ValueError:
                    raise ValueError(f"--zoom takes fit or a percentage, got {part!r}") from None
                if not (math.isfinite(percent) and 5.0 <= percent <= 1600.0):
                    raise ValueError(f"--zoom percentages lie within 5-1600, got {part!r}")
                part = f"{percent:g}"
            zooms.append(part)
    return zooms or ["fit"]


def show_zoom(app, win, zoom: str) -> float | None:
    """Fit the canvas (upright) to the window, then zoom to ``zoom`` percent about the canvas
    centre unless it is ``fit``; returns the stroke's radius for that view, m (None: the
    default circle)."""
    widget = win.canvas_widget
    widget.nav.fit_to_window()
    widget.nav.reset_rotation()
    radius = None
    if zoom != "fit":
        widget.nav.zoom_to(float(zoom) / 100.0)
        x0, y0, x1, y1 = widget.view().visible_box_m()
        radius = min(0.25 * win.shared.canvas.size_m[1], 0.3 * min(x1 - x0, y1 - y0))
    for _ in range(20):  # the new view drawn once before the timing
        app.processEvents()
        time.sleep(0.01)
    return radius


def process_cpu_s(pid: int | None) -> float | None:
    """CPU time (user + system) another process of ours has used so far, s; None if unknown."""
    if pid is None:
        return None
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError):
        return None


def paint_steps(win) -> int:
    """Paint steps the window's simulation has taken (the worker's status says it in both forms;
    a thread is asked directly, its status lagging a step)."""
    session = getattr(win.worker, "session", None)
    if session is not None:
        return session.stats.paint_steps
    return win.worker.status.get().paint_steps


def worker_cpu_clock(win):
    """A function giving the CPU time the simulation has used, s: its thread's, or its whole
    process's in the process form."""
    ident = getattr(win.worker, "ident", None)
    if ident is not None:
        clock = time.pthread_getcpuclockid(ident)
        return lambda: time.clock_gettime(clock)
    pid = win.worker.pid
    return lambda: process_cpu_s(pid) or 0.0


def paint(
    app, win, seconds: float, radius_m: float | None = None, lift: bool = False
) -> dict[str, float | None]:
    """Paint for ``seconds`` (a circle of ``radius_m``, see :func:`circle_m`; ``lift``: the pen
    is lifted at the end); returns the measured rates."""
    from PySide6.QtCore import QEvent

    widget = win.canvas_widget
    send = tablet_sender(widget)
    if win.link is not None:  # the simulated hand carried to the stroke's start in the air
        win.link.target.set(*circle_m(win, 0.0, radius_m), 0.0, False)
        until = time.perf_counter() + APPROACH_S
        while time.perf_counter() < until:
            app.processEvents()
            time.sleep(0.004)
    frames0, steps0 = widget.frame_count, paint_steps(win)
    drawn0 = widget.drawn_count
    worker_cpu = worker_cpu_clock(win)
    servo_pid = None if win.link is None or win.link.process is None else win.link.process.pid
    servo0 = process_cpu_s(servo_pid)
    cpu0 = (worker_cpu(), time.thread_time(), time.process_time())
    start = time.perf_counter()
    first = True
    x_m = y_m = 0.0
    while (t := time.perf_counter() - start) < seconds:
        x_m, y_m = circle_m(win, t, radius_m)
        pressure = PRESSURE * min(1.0, t / PRESS_S)
        if win.link is not None:
            win.link.target.set(x_m, y_m, pressure, True)
        else:
            kind = QEvent.Type.TabletPress if first else QEvent.Type.TabletMove
            send(kind, *widget.mapping().to_widget(x_m, y_m), pressure)
        first = False
        app.processEvents()
        time.sleep(0.004)
    elapsed = time.perf_counter() - start
    cpu1 = (worker_cpu(), time.thread_time(), time.process_time())
    if lift and win.link is not None:
        win.link.target.set(x_m, y_m, 0.0, False)
    elif lift:
        send(QEvent.Type.TabletRelease, *widget.mapping().to_widget(x_m, y_m), 0.0)
    servo1 = process_cpu_s(servo_pid)
    servo_cpu = None if servo0 is None or servo1 is None else (servo1 - servo0) / elapsed
    return {
        # the servo process's CPU time per wall second (user and system), None without one
        "servo_cpu": servo_cpu,
        "seconds": elapsed,
        # passes of the render loop (each leaves the screen up to date), and those that had
        # something to redraw (new paint, the brush outline or the force arrow moved)
        "frame_hz": (widget.frame_count - frames0) / elapsed,
        "drawn_hz": (widget.drawn_count - drawn0) / elapsed,
        "sim_hz": (paint_steps(win) - steps0) / elapsed,
        # CPU time per wall second: the simulation worker thread, the GUI thread, the whole app
        # process (servo thread and llvmpipe's threads included). A worker far below 1 while
        # the app as a whole is not CPU-bound would point at the interpreter lock.
        "worker_cpu": (cpu1[0] - cpu0[0]) / elapsed,
        "gui_cpu": (cpu1[1] - cpu0[1]) / elapsed,
        "app_cpu": (cpu1[2] - cpu0[2]) / elapsed,
    }


def headless_rate(seconds: float, journal: Path) -> tuple[float, float, float, np.ndarray]:
    """Paint steps per second of a fresh session, no window and no servo loop, fed the very
    samples and events the window's simulation consumed (its journal), as fast as it can take
    them, for up to ``seconds``; the CPU time it got per wall second; its real-time ratio:
    wall seconds per second of the journal it replayed (NaN when it replayed none); and the
    paint it left on its canvas (P, H, W), metres."""
    from paintapp.app.options import PaintOptions, blank_canvas
    from paintapp.app.settings import PaintSettings, make_preset, make_scene, rebuild_session
    from paintapp.haptics.channel import ForceChannel
    from paintapp.strokes.files import read_strokes

    strokes = read_strokes(journal)
    settings = PaintSettings()
    canvas = blank_canvas(options=PaintOptions())
    kind = strokes.header.input_kind
    preset, scene = make_preset(settings), make_scene(settings, None)
    session = rebuild_session(None, canvas, preset, scene, kind, ForceChannel())
    records = iter(strokes.records)
    first_t = last_t = 0.0
    for record in records:  # up to the first paint step (the hover before it is not timed)
        session.handle(record)
        if session.stats.paint_steps > 0:
            first_t = last_t = record.t_s
            break
    steps0 = session.stats.paint_steps
    cpu0 = time.thread_time()
    start = time.perf_counter()
    for record in records:
        session.handle(record)
        last_t = record.t_s
        if time.perf_counter() - start > seconds:
            break
    elapsed = time.perf_counter() - start
    realtime = elapsed / (last_t - first_t) if last_t > first_t else math.nan
    rate = (session.stats.paint_steps - steps0) / elapsed
    return rate, (time.thread_time() - cpu0) / elapsed, realtime, canvas.paint_m


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=6.0)
    parser.add_argument(
        "--device",
        default="none",
        metavar="none|sim|openhaptics[:NAME]|dhd|haply[:ID]",
        help="the haptic device (default: none); vendor devices need their library or service",
    )
    parser.add_argument("--servo", choices=("process", "thread"), default="process")
    parser.add_argument("--simulation", choices=("thread", "process"), default="thread",
                        help="where the window's simulation runs")  # fmt: skip
    parser.add_argument("--headless-seconds", type=float, default=None,
                        help="length of the headless run (default: --seconds; 0 skips it)")  # fmt: skip
    parser.add_argument("--bare-seconds", type=float, default=None,
                        help="length of the bare loop's run with a device (default: --seconds; "
                             "0 skips it)")  # fmt: skip
    parser.add_argument("--rounds", type=int, default=1,
                        help="repeat the measurement; prints each round and the medians")  # fmt: skip
    parser.add_argument("--json", type=Path, help="write the figures to this JSON file")
    parser.add_argument("--switch-interval-ms", type=float, default=None,
                        help="the interpreter's switch interval in the app (default: as is)")  # fmt: skip
    parser.add_argument("--screenshot", type=Path, help="save the window here at the end")
    parser.add_argument(
        "--surface",
        default="smooth",
        metavar="NAME",
        help="the canvas's surface (default smooth; see paintapp paint --surface)",
    )
    parser.add_argument("--zoom", action="append", metavar="fit,100,800",
                        help="paint at each of these views in turn: fit, or a zoom in percent "
                             "(5-1600; 100: one canvas texel per device pixel); default fit")  # fmt: skip
    args = parser.parse_args()
    if args.rounds < 1 or not args.seconds > 0:
        parser.error("--rounds must be at least 1 and --seconds positive")
    try:
        args.zooms = parse_zooms(args.zoom)
    except ValueError as exc:
        parser.error(str(exc))
    xvfb = private_display()
    try:
        run(args)
    finally:
        if xvfb is not None:
            sys.stdout.flush()
            xvfb.terminate()
            os._exit(0)  # skip Qt's teardown: its display is gone


def wait_until_ready(app, win, timeout_s: float = 300.0) -> None:
    """Wait until the servo loop publishes the stylus, a frame has been drawn and the simulation
    is prepared (its warm-up stroke): a servo process that starts late (a loaded machine) or a
    warm-up that compiles must not eat the timed stroke."""
    start = time.perf_counter()
    while time.perf_counter() - start < timeout_s:
        servo_up = win.link is None or win.link.states.latest()[1] is not None
        ready = win.worker.status.get().ready
        if servo_up and ready and win.canvas_widget.frame_count > 0:
            return
        app.processEvents()
        time.sleep(0.01)
    print(f"warning: not ready after {timeout_s:.0f} s (servo, first frame or warm-up); timing "
          "anyway")  # fmt: skip


#: The figures the summary table shows, in its order, with their formats.
SUMMARY = (
    ("servo achieved rate (Hz)", "{:.1f}"),
    ("servo lateness p99 (ms)", "{:.3f}"),
    ("servo lateness max (ms)", "{:.2f}"),
    ("bare loop lateness p99 (ms)", "{:.3f}"),
    ("bare loop lateness max (ms)", "{:.2f}"),
    ("bare loop stalls over 2 ms", "{:.0f}"),
    ("simulation rate", "{:.1f}"),
    ("headless simulation rate", "{:.1f}"),
    ("window share of headless", "{:.0%}"),
    ("worker CPU per second, window", "{:.2f}"),
    ("servo process CPU per second", "{:.2f}"),
    ("worker CPU per paint step, window (ms)", "{:.1f}"),
    ("worker CPU per paint step, headless (ms)", "{:.1f}"),
    ("frame rate", "{:.1f}"),
    ("servo tick cost p50 (us)", "{:.0f}"),
    ("app's longest silence (ms)", "{:.0f}"),
    ("host CPU steal, window run", "{:.1%}"),
    ("host CPU steal peak, window run", "{:.1%}"),
    ("host CPU steal, headless run", "{:.1%}"),
)


def run(args: argparse.Namespace) -> None:
    rounds = []
    for index in range(args.rounds):
        if args.rounds > 1:
            print(f"--- round {index + 1} of {args.rounds}")
        tmp = Path(tempfile.mkdtemp(prefix="bench-app-"))  # the journal and recovery files
        try:
            rounds.append(measure(args, tmp))
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
    figures = medians(rounds)
    if args.rounds > 1:
        print(summary_table(rounds, figures))
    if args.json is not None:
        figures["rounds"] = rounds
        args.json.write_text(json.dumps(figures, indent=2, default=str) + "\n")
        print(f"wrote {args.json}")


def medians(rounds: list[dict[str, object]]) -> dict[str, object]:
    """Each numeric figure's median over the rounds (other figures: the last round's)."""
    out: dict[str, object] = {}
    for key in rounds[-1]:
        values = [r[key] for r in rounds if key in r]
        numeric = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values)
        out[key] = statistics.median(values) if numeric else values[-1]  # type: ignore[type-var]
    return out


def summary_table(rounds: list[dict[str, object]], figures: dict[str, object]) -> str:
    """A Markdown table: the :data:`SUMMARY` figures of every round and their medians."""
    head = " | ".join(f"round {i + 1}" for i in range(len(rounds)))
    lines = [f"| figure | {head} | median |", "|---" * (len(rounds) + 2) + "|"]
    for key, fmt in SUMMARY:
        if key not in figures:
            continue
        cells = [fmt.format(r[key]) if key in r else "-" for r in rounds]
        lines.append(f"| {key} | {' | '.join(cells)} | {fmt.format(figures[key])} |")
    for key in figures:
        if key.startswith(("frame rate at ", "simulation rate at ")):
            cells = [f"{r[key]:.1f}" if key in r else "-" for r in rounds]
            lines.append(f"| {key} | {' | '.join(cells)} | {figures[key]:.1f} |")
    return "\n".join(lines)


def measure(args: argparse.Namespace, tmp: Path) -> dict[str, object]:
    """One round: the window run, then the headless run of its journal; returns the figures."""
    from paintapp.app.haptic_link import parse_device
    from paintapp.app.launch import create_window
    from paintapp.app.options import PaintOptions
    from paintapp.app.settings import PaintSettings
    from paintapp.bench.host_steal import StealMonitor
    from paintapp.canvas.edges import paint_edge_widths

    if args.switch_interval_ms is not None:
        sys.setswitchinterval(1e-3 * args.switch_interval_ms)
    options = PaintOptions(
        device=parse_device(args.device), recovery_dir=tmp, autosave_s=0, recover="no",
        servo=args.servo, record=tmp / "bench.jsonl", simulation=args.simulation,
        settings=PaintSettings(surface=args.surface),
    )  # fmt: skip
    figures: dict[str, object] = {"device": args.device, "load_before": os.getloadavg()[0]}
    app, win = create_window(options, interactive=False)
    for _ in range(100):
        app.processEvents()
        time.sleep(0.01)
    wait_until_ready(app, win)
    win.load_pigment("ultramarine_blue")
    win.hud.show_grid = True
    zooms = getattr(args, "zooms", ["fit"])
    several = len(zooms) > 1
    with StealMonitor() as window_steal:
        rates = paint(app, win, args.seconds, show_zoom(app, win, zooms[0]), lift=several)
    print(f"window {win.canvas_widget.width()}x{win.canvas_widget.height()} px, "
          f"device {args.device}, {rates['seconds']:.1f} s painting")  # fmt: skip
    if several:
        figures |= zoom_figures(zooms[0], rates)
        for zoom in zooms[1:]:
            radius = show_zoom(app, win, zoom)
            win.load_pigment("ultramarine_blue")  # a full brush: each view paints wet
            figures |= zoom_figures(zoom, paint(app, win, args.seconds, radius, lift=True))
    print(f"frame rate      {rates['frame_hz']:7.1f} Hz ({rates['drawn_hz']:.1f} Hz with changes)")
    print(f"simulation rate {rates['sim_hz']:7.1f} paint steps/s")
    servo_cpu = rates["servo_cpu"]
    servo_text = "" if servo_cpu is None else f", servo process {servo_cpu:.2f}"
    print(f"CPU per second  worker {rates['worker_cpu']:.2f}, GUI {rates['gui_cpu']:.2f}, "
          f"app process {rates['app_cpu']:.2f}{servo_text} "
          f"(machine load {os.getloadavg()[0]:.1f})")  # fmt: skip
    if rates["sim_hz"] == 0.0:
        status = win.worker.status.get()
        print(f"no paint step: worker says {status.message!r}; in contact "
              f"{status.in_contact}; tip {status.tip_m}")  # fmt: skip
    figures |= {k: rates[k] for k in ("worker_cpu", "gui_cpu", "app_cpu")}
    figures["worker CPU per second, window"] = rates["worker_cpu"]
    if servo_cpu is not None:
        figures["servo process CPU per second"] = servo_cpu
    figures |= {
        "seconds": rates["seconds"],
        "frame rate": rates["frame_hz"],
        "frames with changes": rates["drawn_hz"],
    }
    figures["simulation rate"] = rates["sim_hz"]
    print(f"host CPU steal  {window_steal.describe()} of the machine's CPU time (half seconds)")
    if window_steal.share is not None:
        figures["host CPU steal, window run"] = window_steal.share
        figures["host CPU steal peak, window run"] = window_steal.peak
    if win.link is not None:
        link = win.link
        rate, jitter, _ = link.live()
        print(f"servo (live)    {rate:7.1f} Hz, tick-interval jitter p99 {jitter:.3f} ms")
        print(f"servo where     {link.mode}: {link.granted}")
        figures |= {"servo mode": link.mode, "servo granted": link.granted}
        figures["servo fault"] = link.fault
        report = link.stop()
        timing = report.timing if report is not None else None
        if timing is not None:
            for label, value in timing.rows():
                print(f"servo {label:22s} {value}")
                figures[f"servo {label}"] = float(value)
        if link.process is not None:
            audit = link.process.audit()
            print(f"servo device writes {audit.get('writes', 0):.0f}, non-finite "
                  f"{audit.get('nonfinite_writes', 0):.0f}, over the limit "
                  f"{audit.get('over_limit_writes', 0):.0f}")  # fmt: skip
            figures["servo audit"] = audit
            silence = audit.get("longest_app_silence_s", 0.0)
            print(f"app's longest silence {1e3 * silence:.0f} ms (the servo process's longest "
                  "wait for a heartbeat)")  # fmt: skip
            figures["app's longest silence (ms)"] = 1e3 * silence
    if args.screenshot is not None:
        win.grab().save(str(args.screenshot))
        print(f"wrote {args.screenshot}")
    win.close()
    app.processEvents()
    figures["load_after"] = os.getloadavg()[0]
    headless_s = args.seconds if args.headless_seconds is None else args.headless_seconds
    if headless_s > 0:
        with StealMonitor() as headless_steal:
            headless, headless_cpu, realtime, paint_m = headless_rate(
                headless_s, tmp / "bench.jsonl"
            )
        share = rates["sim_hz"] / headless if headless > 0 else 0.0
        print(f"headless rate   {headless:7.1f} paint steps/s (window: {100 * share:.0f} %), "
              f"CPU per second {headless_cpu:.2f} (machine load {os.getloadavg()[0]:.1f})")  # fmt: skip
        print(f"headless replay {realtime:7.2f} s per recorded s (real-time ratio of the journal)")
        figures["headless real-time ratio"] = realtime
        edges = paint_edge_widths(paint_m)
        for width in edges:
            print(f"headless canvas {width.describe()}")
        figures["headless edge width"] = edges[0].width_texels
        figures["headless local edge width"] = edges[1].width_texels
        figures |= {"headless simulation rate": headless, "window share of headless": share}
        figures["headless_cpu"] = headless_cpu
        if rates["sim_hz"] > 0 and headless > 0 and headless_cpu > 0:
            # the share, split: the worker's CPU per wall second against the headless run's,
            # times the headless run's CPU time per paint step against the window's
            window_ms = 1e3 * rates["worker_cpu"] / rates["sim_hz"]
            headless_ms = 1e3 * headless_cpu / headless
            print(f"worker CPU      {window_ms:.1f} ms a paint step in the window, "
                  f"{headless_ms:.1f} ms headless")  # fmt: skip
            figures["worker CPU per paint step, window (ms)"] = window_ms
            figures["worker CPU per paint step, headless (ms)"] = headless_ms
        print(f"host CPU steal  {headless_steal.describe()} during the headless run")
        if headless_steal.share is not None:
            figures["host CPU steal, headless run"] = headless_steal.share
    bare_s = args.seconds if args.bare_seconds is None else args.bare_seconds
    if args.device != "none" and bare_s > 0:
        figures |= bare_loop(bare_s)
    return figures


def zoom_figures(zoom: str, rates: dict[str, float | None]) -> dict[str, object]:
    """Prints and returns the frame and simulation rates measured at view ``zoom``, keyed by
    the view."""
    label = "fit" if zoom == "fit" else f"{zoom} %"
    print(f"at {label:8s} frame rate {rates['frame_hz']:7.1f} Hz ({rates['drawn_hz']:.1f} Hz "
          f"with changes), simulation rate {rates['sim_hz']:7.1f} paint steps/s")  # fmt: skip
    return {
        f"frame rate at {label}": rates["frame_hz"],
        f"frames with changes at {label}": rates["drawn_hz"],
        f"simulation rate at {label}": rates["sim_hz"],
    }


def bare_loop(seconds: float) -> dict[str, object]:
    """The machine's own floor: the servo process's clock and real-time settings with an empty
    tick, alone on the idle machine (:mod:`paintapp.haptics.bare_loop`)."""
    from paintapp.bench.host_steal import StealMonitor
    from paintapp.haptics.bare_loop import STALL_S, measure_bare_loop

    with StealMonitor() as steal:
        try:
            bare = measure_bare_loop(seconds)
        except RuntimeError as exc:
            print(f"bare loop       not measured: {exc}")
            return {}
    print(f"bare loop       {bare.describe()}; host CPU steal {steal.describe()}")
    if bare.listed:
        stalls = ", ".join(f"{1e3 * late:.1f} ms at {at:.2f} s" for at, late in bare.listed[:8])
        print(f"bare loop       stalls over {1e3 * STALL_S:g} ms: {stalls}")
    t = bare.timing
    return {
        "bare loop lateness p99 (ms)": 1e3 * t.lateness_p99_s,
        "bare loop lateness max (ms)": 1e3 * t.lateness_max_s,
        "bare loop stalls over 2 ms": bare.stalls,
        "bare loop granted": bare.granted,
    }


if __name__ == "__main__":
    main()
