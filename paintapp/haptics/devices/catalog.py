"""What devices there are, as lines of text for ``paintapp devices``."""

from __future__ import annotations

from paintapp.haptics.device import DeviceInfo, DeviceNotFoundError
from paintapp.haptics.devices.hid_descriptor import (
    INPUT,
    OUTPUT,
    PAGE_GENERIC_DESKTOP,
    PAGE_PID,
    parse_report_descriptor,
)
from paintapp.haptics.devices.hid_stylus import INFO_ID, INFO_SIZE, decode_info
from paintapp.haptics.devices.hid_transport import STYLUS_USAGE_PAGE, enumerate_hid, open_hid
from paintapp.haptics.devices.simulated import SIMULATED_INFO


def describe(info: DeviceInfo) -> str:
    """One line: actuation and limits."""
    parts = [info.actuation, f"senses {info.dof_sensed} DOF"]
    if info.has_force:
        parts.append(f"max {info.max_force_n:g} N")
    if info.has_torque:
        parts.append(f"{info.max_torque_nm:g} N m")
    if info.max_stiffness_n_per_m:
        parts.append(f"stiffness {info.max_stiffness_n_per_m:g} N/m")
    w = info.workspace_m
    parts.append(f"workspace {w[0] * 100:g} x {w[1] * 100:g} x {w[2] * 100:g} cm")
    return ", ".join(parts)


def builtin_devices() -> list[str]:
    """The devices that need no hardware."""
    return [
        f"simulated  {SIMULATED_INFO.name}: {describe(SIMULATED_INFO)} (a simulated hand)",
        "replay     stroke file playback through the servo loop; records the forces output",
    ]


def vendor_devices() -> list[str]:
    """One line per vendor backend (OpenHaptics, Force Dimension DHD, Haply): found or not
    found and why (:func:`paintapp.haptics.devices.backends.vendor_listing`; opens nothing)."""
    from paintapp.haptics.devices.backends import vendor_listing

    return vendor_listing()


def hid_listing() -> list[str]:
    """Every HID interface found, or why there are none."""
    try:
        entries = enumerate_hid()
    except DeviceNotFoundError as exc:
        return [str(exc)]
    if not entries:
        return ["none found (no HID device is attached, or this user may not access them)"]
    lines = []
    for e in entries:
        name = " ".join(x for x in (e.manufacturer, e.product) if x) or "(unnamed)"
        lines.append(
            f"{e.ids}  {name}  usage {e.usage_page:04x}:{e.usage:04x}  {e.role}  "
            f"path {e.path.decode(errors='replace')}"
        )
    return lines


def probe_hid(
    vendor_id: int | None = None, product_id: int | None = None, path: bytes | None = None
) -> list[str]:
    """Open one HID device, read its report descriptor and say which protocol it speaks.

    Raises:
        DeviceNotFoundError: the device is not attached or cannot be opened.
    """
    transport = open_hid(vendor_id, product_id, path)
    try:
        lines = [f"opened {transport.description}"]
        raw = transport.report_descriptor()
        if not raw:
            return [*lines, "cannot read its report descriptor"]
        d = parse_report_descriptor(raw)
        lines.append(f"report descriptor: {len(raw)} bytes, {len(d.fields)} fields")
        axes = [u for u in (0x30, 0x31, 0x32) if d.find(INPUT, PAGE_GENERIC_DESKTOP, u)]
        lines.append(f"input axes: {', '.join('XYZ'[u - 0x30] for u in axes) or 'none'}")
        pid = d.uses_page(PAGE_PID) and any(f.kind == OUTPUT for f in d.fields)
        lines.append(f"HID PID force feedback: {'yes' if pid else 'no'}")
        if d.uses_page(STYLUS_USAGE_PAGE):
            info, rate, watchdog = decode_info(
                transport.get_feature_report(INFO_ID, INFO_SIZE), "stylus"
            )
            lines.append(
                f"6-DOF stylus protocol: yes, {describe(info)}, {rate} Hz, watchdog {watchdog} ms"
            )
        else:
            lines.append("6-DOF stylus protocol: no")
        return lines
    finally:
        transport.close()
