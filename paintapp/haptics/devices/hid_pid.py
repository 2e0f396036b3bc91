"""USB HID PID force feedback (the "Physical Interface Device" class of force-feedback joysticks
and wheels): one constant-force effect whose magnitude and direction follow the servo force.

Report layout: the example descriptor's in the USB "Device Class Definition for Physical
Interface Devices" 1.0, as open-source force-feedback firmwares follow it; report IDs and the
magnitude range in :class:`PidLayout`. Output reports are padded to the size the device declares
(opening fails, with a clear message, where that is smaller than this layout needs); axes and
buttons are found through the report descriptor (:mod:`paintapp.haptics.devices.hid_descriptor`).

Sequence (:class:`PidDriver`): on start, Device Control "enable actuators", Device Gain full,
feature "Create New Effect" (constant force), feature "PID Block Load" (the effect block index),
"Set Effect" (infinite duration, X and Y axes, direction), "Set Constant Force" 0, "Effect
Operation" start. Each tick: "Set Effect" again only if the direction changed, "Set Constant
Force" only if the magnitude changed. On stop: magnitude 0, "Effect Operation" stop, "PID Block
Free", Device Control "disable actuators". Direction: one byte, 0..255 for 0..360 degrees from
the stick's +y axis toward +x, the way the force pushes (``direction_offset_deg`` adapts other
conventions). The stick's x, y map onto the workspace; button 0 held puts the tip
``pen_down_depth_m`` below the canvas, else it hovers ``hover_m`` above.
"""

from __future__ import annotations

import math
import struct
from dataclasses import dataclass

import numpy as np

from paintapp.haptics.device import DeviceError, DeviceInfo, DeviceNotFoundError
from paintapp.haptics.devices.hid_descriptor import (
    FEATURE,
    INPUT,
    OUTPUT,
    PAGE_BUTTON,
    PAGE_GENERIC_DESKTOP,
    PAGE_PID,
    HidField,
    ReportDescriptor,
    normalize,
    parse_report_descriptor,
    read_field,
)
from paintapp.haptics.devices.hid_transport import HidTransport

EFFECT_CONSTANT = 1
OP_START, OP_START_SOLO, OP_STOP = 1, 2, 3
CTRL_ENABLE, CTRL_DISABLE, CTRL_STOP_ALL, CTRL_RESET = 1, 2, 3, 4
LOAD_SUCCESS, LOAD_FULL, LOAD_ERROR = 1, 2, 3
AXES_X, AXES_Y, DIRECTION_ENABLE = 0x01, 0x02, 0x04
DURATION_INFINITE, NO_TRIGGER_BUTTON = 0xFFFF, 0xFF

SET_EFFECT = struct.Struct(
    "<BBBHHHBBBBB"
)  # id block type duration repeat period gain trig axes dx dy
SET_CONSTANT_FORCE = struct.Struct("<BBh")  # id block magnitude
EFFECT_OPERATION = struct.Struct("<BBBB")  # id block operation loop-count
BLOCK_FREE = struct.Struct("<BB")  # id block
DEVICE_CONTROL = struct.Struct("<BB")  # id control
DEVICE_GAIN = struct.Struct("<BB")  # id gain
CREATE_NEW_EFFECT = struct.Struct("<BBH")  # id type byte-count (feature, set)
BLOCK_LOAD = struct.Struct("<BBBH")  # id block status pool-available (feature, get)


@dataclass(frozen=True)
class PidLayout:
    """Report IDs and value ranges (defaults: the PID 1.0 example descriptor)."""

    set_effect_id: int = 0x01
    set_constant_force_id: int = 0x05
    effect_operation_id: int = 0x0A
    block_free_id: int = 0x0B
    device_control_id: int = 0x0C
    device_gain_id: int = 0x0D
    create_new_effect_id: int = 0x05
    block_load_id: int = 0x06
    magnitude_max: int = 10000

    def outputs(self) -> dict[int, int]:
        """Output report ID -> payload bytes this layout writes (without the ID byte)."""
        return {
            self.set_effect_id: SET_EFFECT.size - 1,
            self.set_constant_force_id: SET_CONSTANT_FORCE.size - 1,
            self.effect_operation_id: EFFECT_OPERATION.size - 1,
            self.block_free_id: BLOCK_FREE.size - 1,
            self.device_control_id: DEVICE_CONTROL.size - 1,
            self.device_gain_id: DEVICE_GAIN.size - 1,
        }


@dataclass(frozen=True)
class PidConfig:
    """What a joystick cannot tell us: its force in newtons, and how its axes map to a canvas.

    Attributes:
        max_force_n: the force at full magnitude, N (measure it, or a conservative guess).
        max_stiffness_n_per_m, max_damping_ns_per_m: gains it renders stably.
        workspace_m: the canvas area the stick's full travel covers (x, y, z extents), m.
        pen_down_depth_m, hover_m: tip height with button 0 held / released, m.
        direction_offset_deg: added to the direction angle (devices with another convention).
    """

    max_force_n: float = 2.0
    max_stiffness_n_per_m: float = 400.0
    max_damping_ns_per_m: float = 2.0
    workspace_m: tuple[float, float, float] = (0.2, 0.2, 0.02)
    pen_down_depth_m: float = 0.002
    hover_m: float = 0.01
    direction_offset_deg: float = 0.0


@dataclass(frozen=True)
class JoystickInput:
    """A decoded joystick input report: axes in [-1, 1] and the button bits."""

    x: float
    y: float
    buttons: int


def direction_byte(fx: float, fy: float, offset_deg: float = 0.0) -> int:
    """Direction of (fx, fy) as 0..255 for 0..360 degrees from +y toward +x."""
    angle = math.degrees(math.atan2(fx, fy)) + offset_deg
    return round(angle / 360.0 * 256.0) % 256


def direction_vector(byte: int, offset_deg: float = 0.0) -> np.ndarray:
    """Unit (x, y) vector of a direction byte (inverse of :func:`direction_byte`)."""
    angle = math.radians(byte / 256.0 * 360.0 - offset_deg)
    return np.array([math.sin(angle), math.cos(angle)])


def _pad(report: bytes, declared: int) -> bytes:
    return report + bytes(max(0, 1 + declared - len(report)))


class PidDriver:
    """Host side of HID PID over a :class:`HidTransport`.

    Args:
        transport: an open transport.
        config: force scale and axis mapping.
        layout: report IDs and ranges.
        name: for messages.
    """

    def __init__(
        self,
        transport: HidTransport,
        config: PidConfig | None = None,
        layout: PidLayout | None = None,
        name: str = "force-feedback joystick",
    ) -> None:
        self.transport = transport
        self.config = config or PidConfig()
        self.layout = layout or PidLayout()
        self.name = name
        self.block = 0
        self._direction = -1
        self._magnitude: int | None = None
        self._axes: list[tuple[HidField, int]] = []
        self._buttons: HidField | None = None
        self._descriptor = ReportDescriptor()

    def _check_descriptor(self) -> None:
        d = parse_report_descriptor(self.transport.report_descriptor())
        if not d.uses_page(PAGE_PID):
            raise DeviceNotFoundError(f"{self.name}: no force feedback (HID PID) reports")
        for report_id, need in self.layout.outputs().items():
            have = d.report_bytes(OUTPUT, report_id)
            if have < need:
                raise DeviceNotFoundError(
                    f"{self.name}: output report {report_id} is {have} bytes, the PID layout "
                    f"needs {need}; this device needs a different PidLayout"
                )
        axes = [d.find(INPUT, PAGE_GENERIC_DESKTOP, usage) for usage in (0x30, 0x31)]
        if axes[0] is None or axes[1] is None:
            raise DeviceNotFoundError(f"{self.name}: no X and Y axes in the input report")
        self._axes = [a for a in axes if a is not None]
        self._buttons = next(
            (
                f
                for f in d.fields
                if f.kind == INPUT and f.usages and f.usages[0][0] == PAGE_BUTTON and f.size == 1
            ),
            None,
        )
        self._descriptor = d

    def _write(self, report: bytes) -> None:
        padded = _pad(report, self._descriptor.report_bytes(OUTPUT, report[0]))
        if self.transport.write(padded) != len(padded):
            raise DeviceError(f"{self.name}: short write of report {report[0]}")

    def _create_effect(self) -> int:
        lay = self.layout
        self.transport.send_feature_report(
            _pad(
                CREATE_NEW_EFFECT.pack(lay.create_new_effect_id, EFFECT_CONSTANT, 0),
                self._descriptor.report_bytes(FEATURE, lay.create_new_effect_id),
            )
        )
        size = max(BLOCK_LOAD.size, 1 + self._descriptor.report_bytes(FEATURE, lay.block_load_id))
        reply = self.transport.get_feature_report(lay.block_load_id, size)
        if len(reply) < BLOCK_LOAD.size or reply[0] != lay.block_load_id:
            raise DeviceError(f"{self.name}: no PID Block Load reply")
        _, block, status, _ = BLOCK_LOAD.unpack_from(reply)
        if status != LOAD_SUCCESS or block == 0:
            raise DeviceError(
                f"{self.name}: cannot create a constant-force effect (status {status})"
            )
        return block

    def start(self) -> DeviceInfo:
        """Check the device, create and start a zero constant-force effect; returns its info."""
        self._check_descriptor()
        lay, cfg = self.layout, self.config
        self._write(DEVICE_CONTROL.pack(lay.device_control_id, CTRL_ENABLE))
        self._write(DEVICE_GAIN.pack(lay.device_gain_id, 255))
        self.block = self._create_effect()
        self._set_effect(direction_byte(0.0, 1.0, cfg.direction_offset_deg))
        self._set_magnitude(0)
        self._write(EFFECT_OPERATION.pack(lay.effect_operation_id, self.block, OP_START, 1))
        return DeviceInfo(
            name=self.name,
            kind="hid-pid",
            dof_sensed=2,
            dof_actuated=2,
            max_force_n=cfg.max_force_n,
            max_stiffness_n_per_m=cfg.max_stiffness_n_per_m,
            max_damping_ns_per_m=cfg.max_damping_ns_per_m,
            workspace_m=cfg.workspace_m,
        )

    def _set_effect(self, direction: int) -> None:
        self._write(
            SET_EFFECT.pack(
                self.layout.set_effect_id,
                self.block,
                EFFECT_CONSTANT,
                DURATION_INFINITE,
                0,
                0,
                255,
                NO_TRIGGER_BUTTON,
                AXES_X | AXES_Y | DIRECTION_ENABLE,
                direction,
                0,
            )
        )
        self._direction = direction

    def _set_magnitude(self, magnitude: int) -> None:
        self._write(
            SET_CONSTANT_FORCE.pack(self.layout.set_constant_force_id, self.block, magnitude)
        )
        self._magnitude = magnitude

    def send(self, force_n: np.ndarray) -> None:
        """Command the x, y components of ``force_n`` (N); z cannot be output and is ignored."""
        fx, fy = float(force_n[0]), float(force_n[1])
        size = math.hypot(fx, fy)
        fraction = min(size / self.config.max_force_n, 1.0) if self.config.max_force_n > 0 else 0.0
        magnitude = round(fraction * self.layout.magnitude_max)
        if magnitude > 0:
            direction = direction_byte(fx, fy, self.config.direction_offset_deg)
            if direction != self._direction:
                self._set_effect(direction)
        if magnitude != self._magnitude:
            self._set_magnitude(magnitude)

    def poll(self) -> JoystickInput | None:
        """Drain the queued input reports; the newest joystick reading, or None."""
        newest = None
        while True:
            report = self.transport.read(64, 0)
            if not report:
                return newest
            decoded = self._decode(report)
            newest = decoded if decoded is not None else newest

    def _decode(self, report: bytes) -> JoystickInput | None:
        (fx, ix), (fy, iy) = self._axes
        if self._descriptor.numbered:
            if report[0] != fx.report_id:
                return None
            report = report[1:]
        if len(report) < self._descriptor.report_bytes(INPUT, fx.report_id):
            return None
        buttons = 0
        if self._buttons is not None and self._buttons.report_id == fx.report_id:
            for i in range(self._buttons.count):
                buttons |= read_field(report, self._buttons, i) << i
        x = normalize(read_field(report, fx, ix), fx)
        y = normalize(read_field(report, fy, iy), fy)
        return JoystickInput(x, y, buttons)

    def stop(self) -> None:
        """Zero the effect, stop and free it, disable the actuators."""
        lay = self.layout
        if self.block:
            self._set_magnitude(0)
            self._write(EFFECT_OPERATION.pack(lay.effect_operation_id, self.block, OP_STOP, 0))
            self._write(BLOCK_FREE.pack(lay.block_free_id, self.block))
            self.block = 0
        self._write(DEVICE_CONTROL.pack(lay.device_control_id, CTRL_DISABLE))
