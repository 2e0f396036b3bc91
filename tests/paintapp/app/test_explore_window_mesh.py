"""The exploration window on an OpenFOAM case: the mesh is shown as a slice, the probe follows
the mouse, and its force (taken on local grids resampled off the window's tick) is published."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("vtkmodules")

from paintapp.explore.exploration import Exploration, ProbeSpec
from paintapp.explore.flow_files import FluidOverrides, load_flow
from paintapp.haptics.channel import ForceChannel

CASE = Path(__file__).parents[2] / "data" / "openfoam_cylinder"


def move(widget, x: float, y: float) -> None:
    from PySide6.QtCore import QEvent, QPointF, Qt
    from PySide6.QtGui import QMouseEvent
    from PySide6.QtWidgets import QApplication

    pos = QPointF(x, y)
    event = QMouseEvent(QEvent.Type.MouseMove, pos, widget.mapToGlobal(pos), Qt.MouseButton.NoButton,
                        Qt.MouseButton.NoButton, Qt.KeyboardModifier.NoModifier)  # fmt: skip
    QApplication.sendEvent(widget, event)


def test_a_mesh_is_shown_and_felt(qapp, pump, tmp_path):
    from paintapp.app.explore_window import ExploreWindow

    flow = load_flow([CASE], FluidOverrides(density_kg_m3=1.0))
    exploration = Exploration(flow, ProbeSpec("circle", (0.05,)))
    channel = ForceChannel()
    window = ExploreWindow(exploration, publish=channel.publish_force)
    window.show()
    try:
        rgb = window.slice_rgb()
        assert rgb.shape[1] > rgb.shape[0] > 10  # the channel, wider than high
        grey = np.all(rgb == 63, axis=-1)
        assert 0 < grey.mean() < 0.05  # the cylinder, outside the mesh
        p = window.to_screen(np.array([0.5, 0.2]))
        move(window, p.x(), p.y())
        pump(0.5)
        _, sample = channel.latest()
        assert sample is not None and np.all(np.isfinite(sample.force))
        assert exploration.resampler is not None and exploration.resampler.background
        window.grab().save(str(tmp_path / "mesh.png"))
        assert (tmp_path / "mesh.png").stat().st_size > 1000
    finally:
        window.close()
        window.deleteLater()
