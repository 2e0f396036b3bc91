"""HID enumeration, opening and error wrapping (no hardware is attached on test machines)."""

from __future__ import annotations

import pytest

from common.errors import InputError
from paintapp.haptics.device import DeviceError, DeviceNotFoundError
from paintapp.haptics.devices import hid_transport as ht
from paintapp.haptics.devices.hid_descriptor import parse_report_descriptor, read_field


def entry(page: int, usage: int) -> ht.HidDeviceEntry:
    return ht.HidDeviceEntry(b"/dev/hidraw0", 0x1234, 0xABCD, "", "Acme", "Stick", page, usage, 0)


def test_roles_from_usage() -> None:
    assert entry(ht.STYLUS_USAGE_PAGE, ht.STYLUS_USAGE).role.startswith("6-DOF stylus")
    assert entry(0x01, 0x04).role.startswith("joystick")
    assert entry(0x01, 0x06).role == "other"  # a keyboard
    assert entry(0x01, 0x04).ids == "1234:abcd"


def test_enumeration_is_converted(monkeypatch: pytest.MonkeyPatch) -> None:
    import hid

    fake = [
        {
            "path": b"/dev/hidraw3",
            "vendor_id": 0x046D,
            "product_id": 0xC294,
            "serial_number": None,
            "manufacturer_string": "Logitech",
            "product_string": "Wheel",
            "usage_page": 1,
            "usage": 4,
            "interface_number": 0,
        }
    ]
    monkeypatch.setattr(hid, "enumerate", lambda vid=0, pid=0: fake)
    (e,) = ht.enumerate_hid()
    assert e.ids == "046d:c294" and e.product == "Wheel" and e.serial_number == ""


def test_opening_a_missing_device_is_a_clear_input_error() -> None:
    with pytest.raises(DeviceNotFoundError, match="no HID device 1234:5678") as info:
        ht.open_hid(0x1234, 0x5678)
    assert isinstance(info.value, InputError)
    with pytest.raises(DeviceNotFoundError, match="cannot open"):
        ht.open_hid(path=b"/dev/hidraw-does-not-exist")
    with pytest.raises(DeviceNotFoundError, match="VENDOR:PRODUCT"):
        ht.parse_ids("12345")
    with pytest.raises(DeviceNotFoundError, match="VENDOR:PRODUCT"):
        ht.parse_ids("99999:1")  # vendor ids are 16 bits
    assert ht.parse_ids("046d:C294") == (0x046D, 0xC294)


class FailingHandle:
    def set_nonblocking(self, v: int) -> int:
        return 0

    def read(self, size: int, timeout_ms: int = 0) -> list[int]:
        raise OSError("read error")

    def write(self, data: bytes) -> int:
        return -1

    def close(self) -> None: ...


def test_io_failures_become_device_errors() -> None:
    t = ht.HidapiTransport(FailingHandle(), "test device")
    with pytest.raises(DeviceError, match="unplugged"):
        t.read(64)
    with pytest.raises(DeviceError, match="write failed"):
        t.write(b"\x02" + bytes(31))
    t.close()
    with pytest.raises(DeviceError, match="closed"):
        t.read(64)


def test_descriptor_parser_handles_signed_fields_push_pop_and_truncation() -> None:
    desc = bytes(
        [
            0x05,
            0x01,
            0x09,
            0x04,
            0xA1,
            0x01,
            0xA4,  # Push
            0x15,
            0x81,
            0x25,
            0x7F,
            0x75,
            0x08,
            0x95,
            0x01,
            0x09,
            0x30,
            0x81,
            0x02,  # X: i8
            0xB4,  # Pop: logical range back to unset
            0x75,
            0x04,
            0x95,
            0x01,
            0x81,
            0x03,  # 4 bits of padding
            0x15,
            0x00,
            0x25,
            0x0F,
            0x75,
            0x04,
            0x95,
            0x01,
            0x09,
            0x31,
            0x81,
            0x02,  # Y: u4
            0xC0,
        ]
    )
    d = parse_report_descriptor(desc)
    x, _ = d.find("input", 0x01, 0x30)
    y, _ = d.find("input", 0x01, 0x31)
    assert not d.numbered and d.report_bytes("input", 0) == 2
    payload = bytes([0xF6, 0xB0])  # x = -10, padding, y = 11
    assert read_field(payload, x) == -10 and read_field(payload, y) == 11
    with pytest.raises(InputError, match="truncated"):
        parse_report_descriptor(desc[:-4] + bytes([0x26, 0xFF]))
