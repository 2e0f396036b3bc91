"""``paintapp devices [--probe VID:PID | --path PATH]``: list the haptic and input devices.

Lists the built-in devices (simulated stylus, stroke replay), the vendor backends (OpenHaptics,
Force Dimension DHD, Haply Inverse Service: found, or what to install and where it was looked for)
and every HID interface hidapi finds, with what each could be used as. ``--probe`` opens one HID device and reads its report descriptor
to say which of our protocols it speaks.
"""

from __future__ import annotations

import argparse


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "devices",
        help="list haptic devices: simulated, replay, OpenHaptics, Force Dimension, Haply, HID",
    )
    group = p.add_mutually_exclusive_group()
    group.add_argument("--probe", metavar="VID:PID", help="open this HID device and inspect it")
    group.add_argument("--path", help="open the HID device at this path and inspect it")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from paintapp.haptics.devices.catalog import (
        builtin_devices,
        hid_listing,
        probe_hid,
        vendor_devices,
    )
    from paintapp.haptics.devices.hid_transport import parse_ids

    if args.probe or args.path:
        ids = parse_ids(args.probe) if args.probe else (None, None)
        path = args.path.encode() if args.path else None
        for line in probe_hid(ids[0], ids[1], path):
            print(line)
        return 0
    print("built-in devices:")
    for line in builtin_devices():
        print(f"  {line}")
    print("haptic devices (vendor libraries and services):")
    for line in vendor_devices():
        print(f"  {line}")
    print("HID devices (hidapi):")
    for line in hid_listing():
        print(f"  {line}")
    return 0
