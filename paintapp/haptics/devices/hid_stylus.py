"""The raw 6-DOF stylus report protocol (version 1), both the byte layout and the host driver.

A device maker implements three reports on a HID interface whose top-level collection has the
vendor usage page 0xFF48, usage 0x01 (:data:`REPORT_DESCRIPTOR` is a complete descriptor to
copy). All multi-byte fields are little-endian; the first byte is the report ID.

Input report 0x01, 32 bytes, sent by the device at its servo rate (ideally 1 kHz):

====== ======== ===========================================================================
offset type     field
====== ======== ===========================================================================
0      u8       report ID = 0x01
1      u8       sequence number, +1 per report (wraps)
2      u8       buttons, bit i = button i held
3      u8       status: bit0 actuators enabled, bit1 fault, bit2 output watchdog expired
4      u32      device timestamp, microseconds (wraps)
8      i32 x3   tip position x, y, z, micrometres (device frame, z up)
20     i16 x4   orientation quaternion w, x, y, z, scaled by 32767
28     u16      tip pressure, 0..65535 = 0..1 (0 if not sensed)
30     u16      reserved, 0
====== ======== ===========================================================================

Output report 0x02, 32 bytes, sent by the host once per servo tick:

====== ======== ===========================================================================
0      u8       report ID = 0x02
1      u8       sequence number, +1 per report (wraps)
2      u8       flags: bit0 enable actuators (clear: output zero), bit1 clear fault
3      u8       reserved, 0
4      i32 x3   force x, y, z, micronewtons
16     i32 x3   torque x, y, z, micronewton-metres
28     u32      reserved, 0
====== ======== ===========================================================================

Feature report 0x03, 40 bytes, read by the host once when it opens the device:

====== ======== ===========================================================================
0      u8       report ID = 0x03
1      u8       protocol version = 1
2      u8       sensed: bits 0-2 position x, y, z; bits 3-5 orientation; bit 6 pressure
3      u8       actuated: bits 0-2 force x, y, z; bits 3-5 torque x, y, z
4      u32      max force, micronewtons
8      u32      max torque, micronewton-metres
12     u32      max stiffness, millinewtons per metre
16     u32      max damping, millinewton-seconds per metre
20     u32 x3   workspace extent x, y, z, micrometres
32     u16      input report rate, Hz
34     u16      output watchdog, ms: the device outputs zero force if no output report came
                for this long
36     u32      reserved, 0
====== ======== ===========================================================================

The device must clamp to its own limits whatever it is sent, output zero while the enable bit is
clear, and enforce its output watchdog.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass

import numpy as np

from paintapp.haptics.device import DeviceError, DeviceInfo, DeviceNotFoundError
from paintapp.haptics.devices.hid_transport import HidTransport

PROTOCOL_VERSION = 1
INPUT_ID, OUTPUT_ID, INFO_ID = 0x01, 0x02, 0x03
INPUT_FORMAT = struct.Struct("<BBBBI3i4hHH")
OUTPUT_FORMAT = struct.Struct("<BBBB3i3iI")
INFO_FORMAT = struct.Struct("<BBBB4I3IHHI")
INPUT_SIZE, OUTPUT_SIZE, INFO_SIZE = INPUT_FORMAT.size, OUTPUT_FORMAT.size, INFO_FORMAT.size
STATUS_ENABLED, STATUS_FAULT, STATUS_WATCHDOG = 0x01, 0x02, 0x04
FLAG_ENABLE, FLAG_CLEAR_FAULT = 0x01, 0x02
_I32 = 2**31 - 1

REPORT_DESCRIPTOR = bytes.fromhex(
    "06 48 FF"  # Usage Page (Vendor 0xFF48)
    "09 01"  # Usage (0x01: 6-DOF stylus)
    "A1 01"  # Collection (Application)
    "15 00"  # Logical Minimum (0)
    "26 FF 00"  # Logical Maximum (255)
    "75 08"  # Report Size (8 bits)
    "85 01"  # Report ID (1)
    "95 1F"  # Report Count (31 bytes)
    "09 02"  # Usage (0x02: stylus state)
    "81 02"  # Input (Data, Variable, Absolute)
    "85 02"  # Report ID (2)
    "95 1F"  # Report Count (31 bytes)
    "09 03"  # Usage (0x03: force command)
    "91 02"  # Output (Data, Variable, Absolute)
    "85 03"  # Report ID (3)
    "95 27"  # Report Count (39 bytes)
    "09 04"  # Usage (0x04: device info)
    "B1 02"  # Feature (Data, Variable, Absolute)
    "C0"  # End Collection
)
"""A complete HID report descriptor for the protocol (39 bytes), for device firmware."""


@dataclass(frozen=True)
class StylusInput:
    """A decoded input report (SI units)."""

    sequence: int
    buttons: int
    status: int
    timestamp_us: int
    position_m: np.ndarray
    orientation_wxyz: np.ndarray
    pressure: float


def _micro(values: np.ndarray) -> list[int]:
    return [int(max(-_I32, min(_I32, round(float(v) * 1e6)))) for v in values]


def encode_input(s: StylusInput) -> bytes:
    """Input report bytes for ``s`` (what a device sends)."""
    q = np.asarray(s.orientation_wxyz, dtype=np.float64)
    q = q / max(float(np.linalg.norm(q)), 1e-12)
    quat = [round(max(-1.0, min(1.0, float(v))) * 32767) for v in q]
    pressure = round(min(max(float(s.pressure), 0.0), 1.0) * 65535)
    return INPUT_FORMAT.pack(
        INPUT_ID,
        s.sequence & 0xFF,
        s.buttons & 0xFF,
        s.status & 0xFF,
        s.timestamp_us & 0xFFFFFFFF,
        *_micro(s.position_m),
        *quat,
        pressure,
        0,
    )


def decode_input(report: bytes) -> StylusInput | None:
    """Decode an input report; None for another report ID or a short report."""
    if len(report) < INPUT_SIZE or report[0] != INPUT_ID:
        return None
    f = INPUT_FORMAT.unpack_from(report)
    q = np.array(f[8:12], dtype=np.float64) / 32767.0
    norm = float(np.linalg.norm(q))
    q = q / norm if norm > 0 else np.array([1.0, 0.0, 0.0, 0.0])
    position = np.array(f[5:8], dtype=np.float64) * 1e-6
    return StylusInput(f[1], f[2], f[3], f[4], position, q, f[12] / 65535.0)


def encode_output(sequence: int, flags: int, force_n: np.ndarray, torque_nm: np.ndarray) -> bytes:
    """Output report bytes (what the host sends); values saturate at the i32 range."""
    return OUTPUT_FORMAT.pack(
        OUTPUT_ID, sequence & 0xFF, flags & 0xFF, 0, *_micro(force_n), *_micro(torque_nm), 0
    )


def decode_output(report: bytes) -> tuple[int, int, np.ndarray, np.ndarray] | None:
    """``(sequence, flags, force_n (3,), torque_nm (3,))`` or None for another report."""
    if len(report) < OUTPUT_SIZE or report[0] != OUTPUT_ID:
        return None
    f = OUTPUT_FORMAT.unpack_from(report)
    return f[1], f[2], np.array(f[4:7]) * 1e-6, np.array(f[7:10]) * 1e-6


def encode_info(info: DeviceInfo, rate_hz: int = 1000, watchdog_ms: int = 50) -> bytes:
    """Feature report bytes describing ``info`` (what a device answers)."""
    sensed = 0b111 | (0b111000 if info.dof_sensed >= 6 else 0) | 0x40
    actuated = (0b111 if info.has_force else 0) | (0b111000 if info.has_torque else 0)
    limits = [
        info.max_force_n * 1e6,
        info.max_torque_nm * 1e6,
        info.max_stiffness_n_per_m * 1e3,
        info.max_damping_ns_per_m * 1e3,
        *(w * 1e6 for w in info.workspace_m),
    ]
    return INFO_FORMAT.pack(
        INFO_ID,
        PROTOCOL_VERSION,
        sensed,
        actuated,
        *(min(round(float(v)), 2**32 - 1) for v in limits),
        rate_hz,
        watchdog_ms,
        0,
    )


def decode_info(report: bytes, name: str) -> tuple[DeviceInfo, int, int]:
    """``(DeviceInfo, input rate Hz, watchdog ms)`` from the feature report."""
    if len(report) < INFO_SIZE or report[0] != INFO_ID:
        raise DeviceNotFoundError(f"{name}: no stylus info report; not a 6-DOF stylus?")
    f = INFO_FORMAT.unpack_from(report)
    if f[1] != PROTOCOL_VERSION:
        raise DeviceNotFoundError(f"{name}: stylus protocol version {f[1]}, expected 1")
    sensed, actuated = f[2], f[3]
    info = DeviceInfo(
        name=name,
        kind="hid-stylus",
        dof_sensed=6 if sensed & 0b111000 else 3,
        dof_actuated=6 if actuated & 0b111000 else (3 if actuated & 0b111 else 0),
        max_force_n=f[4] * 1e-6,
        max_torque_nm=f[5] * 1e-6,
        max_stiffness_n_per_m=f[6] * 1e-3,
        max_damping_ns_per_m=f[7] * 1e-3,
        workspace_m=(f[8] * 1e-6, f[9] * 1e-6, f[10] * 1e-6),
    )
    return info, f[11], f[12]


class StylusDriver:
    """Host side of the protocol over a :class:`HidTransport`.

    Args:
        transport: an open transport.
        name: the device's name for messages and :class:`DeviceInfo`.
    """

    def __init__(self, transport: HidTransport, name: str = "6-DOF stylus") -> None:
        self.transport = transport
        self.name = name
        self._seq = 0
        self.info: DeviceInfo | None = None
        self.dropped_reports = 0
        self._last_in_seq: int | None = None

    def start(self) -> DeviceInfo:
        """Read the device's limits and enable its actuators at zero force."""
        self.info, _, _ = decode_info(
            self.transport.get_feature_report(INFO_ID, INFO_SIZE), self.name
        )
        self.send(np.zeros(3), np.zeros(3), enable=True)
        return self.info

    def poll(self) -> StylusInput | None:
        """Drain the queued input reports; the newest, or None if none came."""
        newest = None
        while True:
            report = self.transport.read(64, 0)
            if not report:
                return newest
            decoded = decode_input(report)
            if decoded is None:
                continue
            if self._last_in_seq is not None:
                self.dropped_reports += (decoded.sequence - self._last_in_seq - 1) % 256
            self._last_in_seq = decoded.sequence
            if decoded.status & STATUS_FAULT:
                raise DeviceError(f"{self.name} reports a fault (status 0x{decoded.status:02x})")
            newest = decoded

    def send(self, force_n: np.ndarray, torque_nm: np.ndarray, enable: bool = True) -> None:
        """Send one output report."""
        self._seq = (self._seq + 1) & 0xFF
        flags = FLAG_ENABLE if enable else 0
        written = self.transport.write(encode_output(self._seq, flags, force_n, torque_nm))
        if written != OUTPUT_SIZE:
            raise DeviceError(f"{self.name}: short write ({written} of {OUTPUT_SIZE} bytes)")

    def stop(self) -> None:
        """Zero force, actuators disabled."""
        self.send(np.zeros(3), np.zeros(3), enable=False)
