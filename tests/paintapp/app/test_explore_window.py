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
