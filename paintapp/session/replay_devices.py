"""The devices a replay can play on, by name (light: the command line lists them in its help)."""

from __future__ import annotations

from dataclasses import replace

from common.errors import InputError
from paintapp.haptics.device import DeviceInfo
from paintapp.haptics.devices.simulated import SIMULATED_INFO

#: Devices a replay can play on, by name: what they output decides what the session models.
REPLAY_DEVICES: dict[str, DeviceInfo] = {
    "6dof": SIMULATED_INFO,
    "3dof": replace(
        SIMULATED_INFO, name="simulated 3-DOF stylus", dof_actuated=3, max_torque_nm=0.0
    ),
    "tablet": replace(
        SIMULATED_INFO,
        name="pen tablet (no force feedback)",
        dof_actuated=0,
        max_force_n=0.0,
        max_torque_nm=0.0,
    ),
}


def replay_device(name: str) -> DeviceInfo:
    """The replay device called ``name``; :class:`InputError` for an unknown one."""
    if name not in REPLAY_DEVICES:
        raise InputError(
            f"unknown device {name!r}; expected one of {', '.join(REPLAY_DEVICES)}", key="device"
        )
    return REPLAY_DEVICES[name]
