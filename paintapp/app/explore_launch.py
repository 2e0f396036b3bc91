"""Starting ``paintapp explore``'s window: the display check, the haptic device and its servo
loop (no canvas contact: the device hovers), the window."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from common.errors import InputError
from paintapp.app.launch import display_available, qt_application

if TYPE_CHECKING:
    from paintapp.explore.exploration import Exploration

NO_DISPLAY = (
    "no display: the exploration window needs a graphical session (DISPLAY or WAYLAND_DISPLAY).\n"
    "Without one, drive the probe along a scripted path:\n"
    "  paintapp explore DATA --path PATH.csv --forces F.csv"
)


def launch_explorer(
    args: argparse.Namespace, build: Callable[[argparse.Namespace], Exploration]
) -> int:
    """Open the window on the data ``args`` name; returns the exit status."""
    from paintapp.app.haptic_link import HapticLink, parse_device
    from paintapp.haptics.device import DeviceNotFoundError

    spec = parse_device(args.device)
    if not display_available():
        raise InputError(NO_DISPLAY)
    exploration = build(args)
    app = qt_application()
    from paintapp.app.explore_window import ExploreWindow

    link = None
    if spec.kind != "none":
        link = HapticLink(spec, force_scale=args.force_scale, mode="process")
        try:
            link.start()
        except DeviceNotFoundError:
            raise
        except (RuntimeError, OSError) as exc:
            print(
                f"servo process unavailable ({exc}); running the servo loop in a thread",
                file=sys.stderr,
            )
            link = HapticLink(spec, force_scale=args.force_scale, mode="thread")
            link.start()
    window = None
    try:
        if link is None:
            window = ExploreWindow(exploration)
        else:
            states = link.states
            target = link.target

            def position() -> np.ndarray | None:
                _, state = states.latest()
                return None if state is None else np.asarray(state.position_m)

            def publish(t: float, force: np.ndarray, torque: np.ndarray) -> None:
                link.forces.publish_force(t, force, torque)

            def aim(device_m: np.ndarray) -> None:
                target.set(float(device_m[0]), float(device_m[1]), 0.0, down=False)

            window = ExploreWindow(exploration, publish, position, aim)
        window.show()
        app.exec()
    finally:
        if window is not None:
            window.timer.stop()
            window.deleteLater()
            app.processEvents()
        if link is not None:
            link.stop()
    return 0
