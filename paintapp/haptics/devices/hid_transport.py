"""HID transport: finding devices and moving reports, behind an interface tests can replace.

:class:`HidTransport` is what the protocol drivers talk to. :class:`HidapiTransport` is the real
one, over the ``hidapi`` package; the in-memory device models of
:mod:`tests.support.hid_models` implement the same interface, so both protocols are tested end
to end without hardware. Reports are ``bytes`` whose first byte is the report ID (0 for devices
that do not number their reports), as hidapi uses them.

Errors: a device that cannot be found or opened raises :class:`DeviceNotFoundError` with a
message for the user; an I/O failure once open raises :class:`DeviceError`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol

from paintapp.haptics.device import DeviceError, DeviceNotFoundError
from paintapp.haptics.devices.hid_descriptor import PAGE_GENERIC_DESKTOP

STYLUS_USAGE_PAGE = 0xFF48
"""Vendor-defined usage page of the raw 6-DOF stylus protocol (``paintapp.haptics.devices.hid_stylus``)."""
STYLUS_USAGE = 0x01
_JOYSTICK_USAGES = {0x04: "joystick", 0x05: "gamepad", 0x08: "multi-axis controller"}


class HidTransport(Protocol):
    """Moves HID reports to and from one open device."""

    def read(self, size: int, timeout_ms: int = 0) -> bytes:
        """One input report (at most ``size`` bytes), or ``b""`` if none came within the timeout."""
        ...

    def write(self, report: bytes) -> int:
        """Send an output report; returns the bytes written."""
        ...

    def get_feature_report(self, report_id: int, size: int) -> bytes:
        """Read a feature report (first byte the report ID)."""
        ...

    def send_feature_report(self, report: bytes) -> int:
        """Send a feature report; returns the bytes written."""
        ...

    def report_descriptor(self) -> bytes:
        """The device's HID report descriptor (``b""`` if unavailable)."""
        ...

    def close(self) -> None:
        """Release the device."""
        ...


@dataclass(frozen=True)
class HidDeviceEntry:
    """One HID interface found by enumeration."""

    path: bytes
    vendor_id: int
    product_id: int
    serial_number: str
    manufacturer: str
    product: str
    usage_page: int
    usage: int
    interface_number: int

    @property
    def role(self) -> str:
        """What this interface could be for us: "6-DOF stylus (raw protocol)",
        "joystick (force feedback if it speaks HID PID)", or "other"."""
        if (self.usage_page, self.usage) == (STYLUS_USAGE_PAGE, STYLUS_USAGE):
            return "6-DOF stylus (raw protocol)"
        if self.usage_page == PAGE_GENERIC_DESKTOP and self.usage in _JOYSTICK_USAGES:
            return f"{_JOYSTICK_USAGES[self.usage]} (force feedback if it speaks HID PID)"
        return "other"

    @property
    def ids(self) -> str:
        """``vvvv:pppp`` in hex."""
        return f"{self.vendor_id:04x}:{self.product_id:04x}"


def _hid_module() -> Any:
    try:
        import hid
    except ImportError as exc:  # the package is a dependency, but its C library may be missing
        raise DeviceNotFoundError(f"HID support is unavailable: {exc}") from exc
    return hid


def enumerate_hid(vendor_id: int = 0, product_id: int = 0) -> list[HidDeviceEntry]:
    """Every HID interface the system reports (filtered by ids if non-zero)."""
    hid = _hid_module()
    try:
        found = hid.enumerate(vendor_id, product_id)
    except OSError as exc:
        raise DeviceNotFoundError(f"cannot enumerate HID devices: {exc}") from exc
    entries = []
    for d in found:
        path = d.get("path") or b""
        entries.append(
            HidDeviceEntry(
                path=path if isinstance(path, bytes) else str(path).encode(),
                vendor_id=int(d.get("vendor_id") or 0),
                product_id=int(d.get("product_id") or 0),
                serial_number=str(d.get("serial_number") or ""),
                manufacturer=str(d.get("manufacturer_string") or ""),
                product=str(d.get("product_string") or ""),
                usage_page=int(d.get("usage_page") or 0),
                usage=int(d.get("usage") or 0),
                interface_number=int(d.get("interface_number") or -1),
            )
        )
    return entries


class HidapiTransport:
    """A transport over an open ``hid.device`` (the hidapi package)."""

    def __init__(self, handle: Any, description: str) -> None:
        self._h = handle
        self.description = description
        self._h.set_nonblocking(1)  # read() with no timeout returns at once if nothing is queued

    def _io(self, what: str, method: str, *args: Any) -> Any:
        if self._h is None:
            raise DeviceError(f"{self.description}: {what} on a closed device")
        try:
            result = getattr(self._h, method)(*args)
        except (OSError, ValueError) as exc:
            raise DeviceError(f"{self.description}: {what} failed ({exc}); unplugged?") from exc
        if isinstance(result, int) and result < 0:
            raise DeviceError(f"{self.description}: {what} failed; unplugged?")
        return result

    def read(self, size: int, timeout_ms: int = 0) -> bytes:
        return bytes(self._io("read", "read", size, timeout_ms))

    def write(self, report: bytes) -> int:
        return int(self._io("write", "write", bytes(report)))

    def get_feature_report(self, report_id: int, size: int) -> bytes:
        return bytes(self._io("feature read", "get_feature_report", report_id, size))

    def send_feature_report(self, report: bytes) -> int:
        return int(self._io("feature write", "send_feature_report", bytes(report)))

    def report_descriptor(self) -> bytes:
        try:
            return bytes(self._h.get_report_descriptor())
        except (OSError, ValueError, AttributeError):
            return b""

    def close(self) -> None:
        if self._h is not None:
            try:
                self._h.close()
            finally:
                self._h = None


def parse_ids(text: str) -> tuple[int, int]:
    """``"046d:c294"`` -> (0x046D, 0xC294)."""
    try:
        vid, pid = text.split(":")
        ids = int(vid, 16), int(pid, 16)
        if not all(0 <= i <= 0xFFFF for i in ids):
            raise ValueError("ids are 16-bit")
        return ids
    except ValueError as exc:
        raise DeviceNotFoundError(
            f"device id {text!r} is not VENDOR:PRODUCT in hex (e.g. 046d:c294)"
        ) from exc


def open_hid(
    vendor_id: int | None = None,
    product_id: int | None = None,
    path: bytes | None = None,
    serial: str | None = None,
) -> HidapiTransport:
    """Open a HID device by vendor/product id (and serial) or by path.

    Raises:
        DeviceNotFoundError: nothing matches, or the system refuses to open it (permissions).
    """
    hid = _hid_module()
    if path is None and (vendor_id is None or product_id is None):
        raise DeviceNotFoundError("give a HID path or a vendor and product id")
    if path is not None:
        what = f"HID device at {path.decode(errors='replace')}"
    else:
        what = f"HID device {vendor_id:04x}:{product_id:04x}"
    if path is None and not enumerate_hid(vendor_id or 0, product_id or 0):
        raise DeviceNotFoundError(
            f"no {what} is attached; `paintapp devices` lists the devices found"
        )
    handle = hid.device()
    try:
        if path is not None:
            handle.open_path(path)
        else:
            handle.open(vendor_id, product_id, serial)
    except (OSError, ValueError) as exc:
        raise DeviceNotFoundError(
            f"cannot open {what} ({exc}); is it attached, and may this user access it "
            "(on Linux, a udev rule for /dev/hidraw*)?",
        ) from exc
    return HidapiTransport(handle, what)
