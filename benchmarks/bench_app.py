"""Frame rate, simulation rate and servo jitter of the painting window while it paints.

    python benchmarks/bench_app.py [--seconds 6] [--device none|sim] [--screenshot OUT.png]

Opens the real window (on the current display, or on a private Xvfb server when there is none),
dips the brush, and paints a synthesized circular stroke for ``--seconds``: as tablet events
sent to the canvas widget (``none``), or as the simulated hand's target (``sim``, which also runs
the 1 kHz servo loop). Prints the display frame rate, the paint steps per second, and with a
device the servo loop's achieved rate, tick-interval jitter and start lateness.
"""

from __future__ import annotations

import argparse
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path


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


def circle_m(win, t: float) -> tuple[float, float]:
    """The stroke: a circle of a quarter of the canvas height, once per 3 s."""
    w, h = win.shared.canvas.size_m
    a = 2.0 * math.pi * t / 3.0
    return 0.5 * w + 0.25 * h * math.cos(a), 0.5 * h + 0.25 * h * math.sin(a)


def paint(app, win, seconds: float) -> dict[str, float]:
    """Paint for ``seconds``; returns the measured rates."""
    from PySide6.QtCore import QEvent

    widget = win.canvas_widget
    send = tablet_sender(widget)
    frames0, steps0 = widget.frame_count, win.worker.session.stats.paint_steps
    start = time.perf_counter()
    first = True
    while (t := time.perf_counter() - start) < seconds:
        x_m, y_m = circle_m(win, t)
        if win.link is not None:
            win.link.target.set(x_m, y_m, 0.8, True)
        else:
            kind = QEvent.Type.TabletPress if first else QEvent.Type.TabletMove
            send(kind, *widget.mapping().to_widget(x_m, y_m), 0.8)
        first = False
        app.processEvents()
        time.sleep(0.004)
    elapsed = time.perf_counter() - start
    return {
        "seconds": elapsed,
        "frame_hz": (widget.frame_count - frames0) / elapsed,
        "sim_hz": (win.worker.session.stats.paint_steps - steps0) / elapsed,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=6.0)
    parser.add_argument("--device", choices=("none", "sim"), default="none")
    parser.add_argument("--screenshot", type=Path, help="save the window here at the end")
    args = parser.parse_args()
    xvfb = private_display()
    try:
        run(args)
    finally:
        if xvfb is not None:
            sys.stdout.flush()
            xvfb.terminate()
            os._exit(0)  # skip Qt's teardown: its display is gone


def run(args: argparse.Namespace) -> None:
    from paintapp.app.haptic_link import parse_device
    from paintapp.app.launch import create_window
    from paintapp.app.options import PaintOptions

    tmp = Path(tempfile.mkdtemp(prefix="bench-app-"))
    options = PaintOptions(
        device=parse_device(args.device), recovery_dir=tmp, autosave_s=0, recover="no"
    )
    app, win = create_window(options, interactive=False)
    for _ in range(100):
        app.processEvents()
        time.sleep(0.01)
    win.load_pigment("ultramarine_blue")
    win.hud.show_grid = True
    rates = paint(app, win, args.seconds)
    print(f"window {win.canvas_widget.width()}x{win.canvas_widget.height()} px, "
          f"device {args.device}, {rates['seconds']:.1f} s painting")  # fmt: skip
    print(f"frame rate      {rates['frame_hz']:7.1f} Hz")
    print(f"simulation rate {rates['sim_hz']:7.1f} paint steps/s")
    if win.link is not None:
        rate, jitter, _ = win.link.clock.live()
        print(f"servo (live)    {rate:7.1f} Hz, tick-interval jitter p99 {jitter:.3f} ms")
        timing = win.link.loop.stop().timing
        if timing is not None:
            for label, value in timing.rows():
                print(f"servo {label:22s} {value}")
    if args.screenshot is not None:
        win.grab().save(str(args.screenshot))
        print(f"wrote {args.screenshot}")
    win.close()
    app.processEvents()


if __name__ == "__main__":
    main()
