"""The vendor device backends by name, for ``--device NAME[:ARG]`` and ``paintapp devices``.

- ``openhaptics[:NAME]``: a 3D Systems Touch or Phantom through OpenHaptics
  (:mod:`.openhaptics`); NAME is the device's name in Touch Setup (the default device if absent).
- ``dhd``: a Force Dimension device or the Novint Falcon (:mod:`.forcedimension`).
- ``haply[:DEVICE_ID]``: a Haply Inverse3 (+ VerseGrip) through the Inverse Service
  (:mod:`.haply`).

Nothing vendor-specific is imported until a device is built: the backend modules import only
the standard library and numpy at the top, and load the vendor's library (or ``websockets``)
when the device is opened. :func:`vendor_listing` only looks for the libraries and the service;
it opens nothing.
"""

from __future__ import annotations

import importlib.util
import socket
import time
from collections.abc import Callable
from urllib.parse import urlsplit

from paintapp.haptics.device import DeviceNotFoundError, HapticDevice

#: Backend names accepted by ``--device``.
VENDOR_NAMES = ("openhaptics", "dhd", "haply")
#: How ``--device`` spells each, for help texts.
VENDOR_SYNTAX = "openhaptics[:NAME]|dhd|haply[:ID]"


def split_device(text: str) -> tuple[str, str] | None:
    """``(name, arg)`` if ``text`` names a vendor backend (``NAME`` or ``NAME:ARG``), else None."""
    name, _, arg = text.partition(":")
    if name not in VENDOR_NAMES:
        return None
    if name == "dhd" and arg:
        raise DeviceNotFoundError(f"dhd takes no argument, got {text!r}")
    return name, arg


def build_vendor_device(
    name: str, arg: str = "", time_source: Callable[[], float] = time.perf_counter
) -> HapticDevice:
    """The vendor device ``name`` (with ``arg``), not yet opened (nothing vendor-side loaded)."""
    if name == "openhaptics":
        from paintapp.haptics.devices.openhaptics import OpenHapticsDevice

        return OpenHapticsDevice(time_source, config_name=arg or None)
    if name == "dhd":
        from paintapp.haptics.devices.forcedimension import ForceDimensionDevice

        return ForceDimensionDevice(time_source)
    if name == "haply":
        from paintapp.haptics.devices.haply import HaplyDevice

        return HaplyDevice(time_source, device_id=arg or None)
    raise DeviceNotFoundError(f"unknown device backend {name!r} (one of {', '.join(VENDOR_NAMES)})")


def _library_line(tag: str, spec_module: str, spec_name: str, use: str) -> str:
    import importlib

    from paintapp.haptics.devices.vendor import LibrarySpec, locate

    spec: LibrarySpec = getattr(importlib.import_module(spec_module), spec_name)
    path = locate(spec)
    if path is None:
        return f"{tag:<12}{spec.not_found()}"
    return f"{tag:<12}{spec.product} found: {path} (not opened; use --device {use})"


def _service_line() -> str:
    from paintapp.haptics.devices.haply import INSTALL_HINT, URI_ENV, service_uri

    tag = f"{'haply':<12}"
    if importlib.util.find_spec("websockets") is None:
        return (
            f"{tag}Haply Inverse3 not available: the websockets package is missing "
            "(pip install websockets, the haptic-fluid-paint[haply] extra)"
        )
    uri = service_uri()
    parts = urlsplit(uri)
    host, port = parts.hostname or "127.0.0.1", parts.port or 10001
    try:
        with socket.create_connection((host, port), timeout=0.2):
            pass
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        return (
            f"{tag}Haply Inverse Service not found at {uri} ({reason}): {INSTALL_HINT}, and "
            f"start it; set {URI_ENV}=ws://HOST:PORT if it listens elsewhere."
        )
    return f"{tag}Haply Inverse Service listening at {uri} (not opened; use --device haply)"


def vendor_listing() -> list[str]:
    """One line per vendor backend: found (where) or not found (what to install, where it
    looked, which environment variable points elsewhere). Loads no vendor library."""
    return [
        _library_line(
            "openhaptics", "paintapp.haptics.devices.openhaptics", "HD_SPEC", "openhaptics"
        ),
        _library_line("dhd", "paintapp.haptics.devices.forcedimension", "DHD_SPEC", "dhd"),
        _service_line(),
    ]
