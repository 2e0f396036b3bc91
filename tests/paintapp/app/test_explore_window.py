"""The exploration window on the bundled Schaefer-Turek 2D-2 flow: the probe follows the mouse,
its force is evaluated, finite, published, and changes where the flow does."""

from __future__ import annotations

import numpy as np
from PySide6.QtCore import QEvent, QPointF, Qt
from PySide6.QtGui import QMouseEvent
from PySide6.QtWidgets import QApplication

from paintapp.explore.exploration import Exploration, ProbeSpec
from paintapp.explore.flow_files import load_flow
from paintapp.haptics.channel import ForceChannel
from paintapp.resources import asset_path


def move(widget, x: float, y: float) -> None:
    pos = QPointF(x, y)
    event = QMouseEvent(QEvent.Type.MouseMove, pos, widget.mapToGlobal(pos), Qt.MouseButton.NoButton,
                        Qt.MouseButton.NoButton, Qt.KeyboardModifier.NoModifier)  # fmt: skip
    QApplication.sendEvent(widget, event)


def test_the_probe_follows_the_mouse_and_its_force_reaches_the_channel(qapp, pump, tmp_path):
    from paintapp.app.explore_window import ExploreWindow

    flow = load_flow([asset_path("flows", "schaefer_turek_2d2.npz")])
    exploration = Exploration(flow, ProbeSpec("circle", (0.05,), depth_m=0.05))
    channel = ForceChannel()
    window = ExploreWindow(exploration, publish=channel.publish_force)
    window.show()
    try:
        pump(0.3)
        forces = {}
        for name, at in (("wake", (0.6, 0.2)), ("inflow", (0.05, 0.2))):
            p = window.to_screen(np.array(at))
            move(window, p.x(), p.y())
            pump(0.3)
            np.testing.assert_allclose(window.probe_m, at, atol=2 * flow.spacing_m.max())
            _, sample = channel.latest()
            assert sample is not None and np.all(np.isfinite(sample.force))
            forces[name] = sample.force.copy()
        assert window.evaluations > 10
        assert not np.allclose(forces["wake"], forces["inflow"])
        window.grab().save(str(tmp_path / "explore.png"))
        assert (tmp_path / "explore.png").stat().st_size > 1000
    finally:
        window.close()
        assert not window.timer.isActive()  # a closed window stops evaluating
        window.deleteLater()
        pump(0.1)


def test_a_simulated_device_drives_the_probe_and_receives_its_force(qapp, pump):
    from paintapp.app.explore_window import ExploreWindow
    from paintapp.app.haptic_link import HapticLink, parse_device

    flow = load_flow([asset_path("flows", "schaefer_turek_2d2.npz")])
    exploration = Exploration(flow, ProbeSpec("circle", (0.05,), depth_m=0.05))
    link = HapticLink(parse_device("sim"), force_scale=2.0, mode="thread")
    link.start()
    try:

        def position():
            _, state = link.states.latest()
            return None if state is None else np.asarray(state.position_m)

        def aim(device_m):
            link.target.set(float(device_m[0]), float(device_m[1]), 0.0, down=False)

        window = ExploreWindow(exploration, link.forces.publish_force, position, aim)
        window.show()
        at = np.array([0.7, 0.25])
        p = window.to_screen(at)
        move(window, p.x(), p.y())
        assert pump(5.0, until=lambda: np.linalg.norm(window.probe_m - at) < 0.01)
        _, sample = link.forces.latest()
        assert sample is not None and np.all(np.isfinite(sample.force))
        window.close()
        window.deleteLater()
        pump(0.1)
    finally:
        report = link.stop()
    assert link.fault is None and report is not None
