"""Fixtures for the app tests: an Xvfb server of our own, the QApplication, a window factory."""

from __future__ import annotations

import os
import shutil
import subprocess
import time
from collections.abc import Callable, Iterator

import pytest


def _start_xvfb() -> tuple[subprocess.Popen, str]:
    """Start Xvfb on a free display number (Xvfb picks it: -displayfd)."""
    read_fd, write_fd = os.pipe()
    proc = subprocess.Popen(
        ["Xvfb", "-displayfd", str(write_fd), "-screen", "0", "1600x1000x24", "-nolisten", "tcp"],
        pass_fds=(write_fd,),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    os.close(write_fd)
    with os.fdopen(read_fd) as pipe:
        number = pipe.readline().strip()
    if not number:
        proc.kill()
        raise RuntimeError("Xvfb did not report a display number")
    return proc, f":{number}"


@pytest.fixture(scope="session")
def xvfb_display() -> Iterator[str]:
    """A private X display for the whole session (skips when Xvfb is not installed)."""
    if shutil.which("Xvfb") is None:
        pytest.skip("Xvfb is not installed (apt-get install xvfb); the window tests need it")
    pytest.importorskip("PySide6", reason="PySide6 is not installed")
    proc, display = _start_xvfb()
    old = {k: os.environ.get(k) for k in ("DISPLAY", "QT_QPA_PLATFORM", "WAYLAND_DISPLAY")}
    os.environ["DISPLAY"] = display
    os.environ["QT_QPA_PLATFORM"] = "xcb"
    os.environ.pop("WAYLAND_DISPLAY", None)
    try:
        yield display
    finally:
        for key, value in old.items():
            if value is None:
                os.environ.pop(key, None)
            else:
                os.environ[key] = value
        proc.terminate()
        try:
            proc.wait(5)
        except subprocess.TimeoutExpired:
            proc.kill()


def _warm_up_kernels() -> None:
    """Compile the painting kernels before any window opens. The window's simulation worker uses
    only the newest input, so a first step that spends many seconds compiling (a fresh checkout
    has no kernel cache) would skip most of a test stroke."""
    from pathlib import Path

    from paintapp.session.playback import replay
    from paintapp.strokes.files import read_strokes

    replay(
        read_strokes(
            Path(__file__).resolve().parents[1] / "session" / "golden" / "grid3d_drag.jsonl"
        )
    )


@pytest.fixture(scope="session")
def qapp(xvfb_display: str):
    """The QApplication (one per process), on the private display."""
    from paintapp.app.launch import qt_application

    _warm_up_kernels()
    return qt_application()


def _pump(app, seconds: float, until: Callable[[], bool] | None = None) -> bool:
    """Process Qt events for up to ``seconds`` (or until ``until()``); True if ``until`` held."""
    end = time.perf_counter() + seconds
    while time.perf_counter() < end:
        app.processEvents()
        if until is not None and until():
            return True
        time.sleep(0.005)
    return until() if until is not None else True


@pytest.fixture
def pump(qapp) -> Callable[..., bool]:
    """``pump(seconds, until=None)``: run the Qt event loop for a while."""
    return lambda seconds, until=None: _pump(qapp, seconds, until)


_DEVICES: dict[str, object] = {}


def tablet_event(widget, kind, x_px: float, y_px: float, pressure: float, tilt=(0.0, 0.0)):
    """A synthesized QTabletEvent (as a pen tablet's driver would deliver) at widget pixels."""
    from PySide6.QtCore import QEvent, QPointF, Qt
    from PySide6.QtGui import QInputDevice, QPointingDevice, QTabletEvent

    caps = QInputDevice.Capability
    device = _DEVICES.get("pen") or QPointingDevice(
        "test stylus",
        1,
        QInputDevice.DeviceType.Stylus,
        QPointingDevice.PointerType.Pen,
        caps.Position | caps.Pressure | caps.XTilt | caps.YTilt | caps.Rotation,
        1,
        3,
    )
    _DEVICES["pen"] = device  # the event refers to it: keep it alive
    pos = QPointF(x_px, y_px)
    held = kind != QEvent.Type.TabletRelease
    buttons = Qt.MouseButton.LeftButton if held else Qt.MouseButton.NoButton
    return QTabletEvent(
        kind, device, pos, widget.mapToGlobal(pos), pressure, tilt[0], tilt[1], 0.0, 0.0, 0.0,
        Qt.KeyboardModifier.NoModifier, Qt.MouseButton.LeftButton, buttons,
    )  # fmt: skip


@pytest.fixture
def stroke(qapp, pump) -> Callable[..., None]:
    """``stroke(window, start_m, end_m, pressure=0.8, steps=40)``: a straight tablet stroke
    between two canvas points, sent to the canvas widget as QTabletEvents."""
    from PySide6.QtCore import QEvent
    from PySide6.QtWidgets import QApplication

    def run(window, start_m, end_m, pressure: float = 0.8, steps: int = 40) -> None:
        widget = window.canvas_widget
        mapping = widget.mapping()
        points = [
            mapping.to_widget(
                start_m[0] + (end_m[0] - start_m[0]) * i / steps,
                start_m[1] + (end_m[1] - start_m[1]) * i / steps,
            )
            for i in range(steps + 1)
        ]
        T = QEvent.Type
        QApplication.sendEvent(widget, tablet_event(widget, T.TabletPress, *points[0], pressure))
        for x, y in points[1:]:
            pump(0.02)
            QApplication.sendEvent(widget, tablet_event(widget, T.TabletMove, x, y, pressure))
        pump(0.05)
        QApplication.sendEvent(widget, tablet_event(widget, T.TabletRelease, *points[-1], 0.0))

    return run


@pytest.fixture
def pen(qapp) -> Callable[..., None]:
    """``pen(window, kind, point_m, pressure=0.8)``: one tablet event ("press", "move" or
    "release") at a canvas point, sent to the canvas widget."""
    from PySide6.QtCore import QEvent
    from PySide6.QtWidgets import QApplication

    kinds = {
        "press": QEvent.Type.TabletPress,
        "move": QEvent.Type.TabletMove,
        "release": QEvent.Type.TabletRelease,
    }

    def send(window, kind: str, point_m, pressure: float = 0.8) -> None:
        widget = window.canvas_widget
        x, y = widget.mapping().to_widget(*point_m)
        pressure = 0.0 if kind == "release" else pressure
        QApplication.sendEvent(widget, tablet_event(widget, kinds[kind], x, y, pressure))

    return send


#: A small canvas at 0.25 mm texels: the window tests' paint steps stay quick.
FAST_CANVAS = {"pixels": (720, 480), "size_m": (0.18, 0.12)}


def window_options(tmp_path, **kw):
    """Options of a test window: journal and recovery in ``tmp_path``, no autosave."""
    from paintapp.app.options import PaintOptions

    return PaintOptions(
        record=tmp_path / "strokes.jsonl",
        recovery_dir=tmp_path / "recovery",
        autosave_s=0,
        recover="no",
        **kw,
    )


@pytest.fixture
def window(qapp, pump, tmp_path):
    """A painting window on :data:`FAST_CANVAS`, rendered once, closed after the test."""
    from paintapp.app.launch import create_window

    _, win = create_window(window_options(tmp_path, **FAST_CANVAS), interactive=False)
    assert pump(5.0, lambda: win.canvas_widget.frame_count > 0), "the canvas never rendered"
    yield win
    win.close()
    pump(0.1)
