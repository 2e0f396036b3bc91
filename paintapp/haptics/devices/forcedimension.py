"""Force Dimension delta, omega, sigma and lambda devices, and the Novint Falcon, through Force
Dimension's DHD library (``libdhd``), as a :class:`~paintapp.haptics.device.HapticDevice`; bound
here with :mod:`ctypes` when opened.

No vendor scheduler: the servo loop's tick calls ``dhdGetPosition`` and friends in
:meth:`~ForceDimensionDevice.read` and ``dhdSetForceAndTorque`` in
:meth:`~ForceDimensionDevice.write`; a call returning -1 raises
:class:`~paintapp.haptics.device.DeviceError`, stopping the loop with zero force.

Frame and units: the DHD frame is x toward the user, y right, z up (origin at the workspace
centre); ours (:mod:`paintapp.haptics.device`) is x right, y away from the user, z up; both m, N,
N m. So ours = (y, -x, z) for positions, forces, torques and orientation (a quarter turn about z).

Safety: the force limit (per model) goes to the library, and the controller's watchdog
(:data:`WATCHDOG_S`) lets the device go limp if our calls stop; brakes come off and forces on only
at the first write, so opening cannot trip it. Close writes zero force and puts the brakes on.

Setup: docs/guide/devices-vendor.md.
"""

from __future__ import annotations

import ctypes
import math
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from paintapp.haptics.device import DeviceError, DeviceInfo, DeviceNotFoundError, DeviceState
from paintapp.haptics.devices.vendor import (
    AxisMap,
    LibrarySpec,
    bind,
    limited,
    load_library,
    quat_from_matrix,
)

DHD_SPEC = LibrarySpec(
    product="Force Dimension DHD (libdhd)",
    env_var="PAINTAPP_LIBDHD",
    loader_names=("dhd",),
    paths=(
        "/usr/local/lib/libdhd.so",
        "/usr/lib/libdhd.so",
        "/opt/forcedimension/lib/libdhd.so",
        "C:\\Windows\\System32\\dhd64.dll",
    ),
    install_hint=(
        "install Force Dimension's SDK (its lib/release/<platform>/libdhd.so; for a Falcon, "
        "the SDK's Falcon support)."
    ),
)

DHD_TIMEGUARD = 1
DHD_ON, DHD_OFF = 1, 0
DHD_DEVICE_ID = -1  # the default device
DHD_DEVICE_OMEGA3, DHD_DEVICE_FALCON, DHD_DEVICE_DELTA3 = 33, 60, 63
#: Continuous force by device type, N (delta.3 20 N, omega.3/6/7 12 N, sigma.7 and lambda.7
#: 20 N, Falcon 8.9 N); anything else gets :data:`FALLBACK_FORCE_N`.
NOMINAL_FORCE_N = {
    63: 20.0,
    64: 20.0,
    33: 12.0,
    34: 12.0,
    35: 12.0,
    36: 12.0,
    37: 12.0,
    60: 8.9,
    104: 20.0,
    105: 20.0,
    106: 20.0,
    107: 20.0,
    108: 20.0,
    109: 20.0,
}
FALLBACK_FORCE_N = 5.0
#: Torque of an active wrist, N m (sigma.7 and lambda.7 class).
NOMINAL_TORQUE_NM = 0.4
#: Stiffest wall rendered stably by type, N/m (data sheets: delta and omega 14.5 N/mm, Falcon
#: about 2 N/mm), and a damping that suits it, N s/m; others get the Falcon's values.
STIFFNESS_N_PER_M = {
    63: 14500.0,
    64: 14500.0,
    33: 14500.0,
    34: 14500.0,
    35: 14500.0,
    36: 14500.0,
    37: 14500.0,
}
FALLBACK_STIFFNESS_N_PER_M = 2000.0
DAMPING_NS_PER_M = 10.0
#: Workspace extents by type, m (delta.3 ~ 0.40, omega ~ 0.16, Falcon ~ 0.10 cube).
WORKSPACE_M = {63: 0.40, 64: 0.40, 60: 0.10}
#: The controller's watchdog: forces off when no call arrives within this time, s.
WATCHDOG_S = 0.02
#: DHD axes -> ours: (y, -x, z).
DHD_AXES = AxisMap(axes=(1, 0, 2), signs=(1.0, -1.0, 1.0))


class DHDLibrary:
    """The subset of ``libdhd`` the backend calls, with signatures set."""

    def __getattr__(self, name: str) -> Any:
        """The bound C functions are set per instance in ``__init__``; this only types them."""
        raise AttributeError(name)

    def __init__(self, lib: ctypes.CDLL) -> None:
        i, d, c, b, u = ctypes.c_int, ctypes.c_double, ctypes.c_byte, ctypes.c_bool, ctypes.c_uint
        dp, s, ub = ctypes.POINTER(d), ctypes.c_char_p, ctypes.c_ubyte
        self.lib = lib
        sig: dict[str, tuple[object, list[object]]] = {
            "dhdOpen": (i, []),
            "dhdClose": (i, [c]),
            "dhdStop": (i, [c]),
            "dhdGetSystemType": (i, [c]),
            "dhdGetSystemName": (s, [c]),
            "dhdHasActiveWrist": (b, [c]),
            "dhdHasWrist": (b, [c]),
            "dhdGetPosition": (i, [dp, dp, dp, c]),
            "dhdGetOrientationFrame": (i, [ctypes.POINTER(d * 9), c]),
            "dhdGetButtonMask": (u, [c]),
            "dhdSetForceAndTorque": (i, [d, d, d, d, d, d, c]),
            "dhdEnableForce": (i, [ub, c]),
            "dhdSetBrakes": (i, [i, c]),
            "dhdSetWatchdog": (i, [ub, c]),
            "dhdErrorGetLastStr": (s, []),
        }
        for name, (restype, argtypes) in sig.items():
            setattr(self, name, bind(lib, DHD_SPEC, name, restype, argtypes))
        # present in newer SDKs only
        self.dhdSetMaxForce = _optional(lib, "dhdSetMaxForce", i, [d, c])
        self.dhdGetMaxForce = _optional(lib, "dhdGetMaxForce", d, [c])
        self.dhdEnableExpertMode = _optional(lib, "dhdEnableExpertMode", i, [])
        self.dhdDisableExpertMode = _optional(lib, "dhdDisableExpertMode", i, [])

    def last_error(self) -> str:
        raw = self.dhdErrorGetLastStr()
        return raw.decode(errors="replace") if raw else "unknown DHD error"


def _optional(lib: ctypes.CDLL, name: str, restype: object, argtypes: list[object]) -> Any:
    try:
        return bind(lib, DHD_SPEC, name, restype, argtypes)
    except DeviceNotFoundError:
        return None


def load_dhd() -> DHDLibrary:
    """Load and bind ``libdhd`` (:class:`DeviceNotFoundError` with what to install if missing)."""
    return DHDLibrary(load_library(DHD_SPEC))


class ForceDimensionDevice:
    """A DHD device as a :class:`HapticDevice`.

    Args:
        time_source: the servo clock's ``now_s``; readings are stamped with it.
        centre_m: our origin in our frame relative to the workspace centre, m.
        watchdog_s: the controller's watchdog time (125 us steps, at most 31.875 ms).
    """

    def __init__(
        self,
        time_source: Callable[[], float] = time.perf_counter,
        centre_m: tuple[float, float, float] = (0.0, 0.0, 0.0),
        watchdog_s: float = WATCHDOG_S,
    ) -> None:
        if not (math.isfinite(watchdog_s) and 125e-6 <= watchdog_s <= 255 * 125e-6):
            raise DeviceNotFoundError(f"watchdog must be 0.125-31.875 ms, got {watchdog_s} s")
        self.time_source = time_source
        self.centre_m = tuple(float(c) for c in centre_m)
        self.watchdog_s = float(watchdog_s)
        self.dhd: DHDLibrary | None = None
        self._info: DeviceInfo | None = None
        self._wrist = False
        self._torque = False
        self._px, self._py, self._pz = ctypes.c_double(), ctypes.c_double(), ctypes.c_double()
        self._frame = (ctypes.c_double * 9)()
        self._live = False
        self.name = "Force Dimension device"

    @property
    def info(self) -> DeviceInfo:
        if self._info is None:
            raise DeviceError(f"{self.name} is not open")
        return self._info

    def open(self) -> None:
        dhd = load_dhd()
        if dhd.dhdOpen() < 0:
            raise DeviceNotFoundError(
                f"no Force Dimension device: {dhd.last_error()} (is it plugged in, powered "
                "and initialised? Falcon: is the Falcon driver installed?)"
            )
        self.dhd = dhd
        try:
            self._info = self._read_info(dhd)
            self._arm(dhd)
        except BaseException:
            self._shutdown()
            raise

    def _read_info(self, dhd: DHDLibrary) -> DeviceInfo:
        kind = dhd.dhdGetSystemType(DHD_DEVICE_ID)
        if kind < 0:
            raise DeviceNotFoundError(f"{self.name}: cannot read its type: {dhd.last_error()}")
        raw = dhd.dhdGetSystemName(DHD_DEVICE_ID)
        self.name = raw.decode(errors="replace") if raw else f"DHD device type {kind}"
        force = NOMINAL_FORCE_N.get(kind, FALLBACK_FORCE_N)
        if dhd.dhdGetMaxForce is not None:
            lib_limit = float(dhd.dhdGetMaxForce(DHD_DEVICE_ID))
            if math.isfinite(lib_limit) and 0 < lib_limit < force:
                force = lib_limit
        self._wrist = bool(dhd.dhdHasWrist(DHD_DEVICE_ID))
        self._torque = bool(dhd.dhdHasActiveWrist(DHD_DEVICE_ID))
        extent = WORKSPACE_M.get(kind, 0.16)
        return DeviceInfo(
            name=self.name,
            kind="forcedimension",
            dof_sensed=6 if self._wrist else 3,
            dof_actuated=6 if self._torque else 3,
            max_force_n=force,
            max_torque_nm=NOMINAL_TORQUE_NM if self._torque else 0.0,
            max_stiffness_n_per_m=STIFFNESS_N_PER_M.get(kind, FALLBACK_STIFFNESS_N_PER_M),
            max_damping_ns_per_m=DAMPING_NS_PER_M,
            workspace_m=(extent, extent, extent),
        )

    def _arm(self, dhd: DHDLibrary) -> None:
        """Hand the limits and the watchdog to the device, then brakes off and forces on."""
        if dhd.dhdSetMaxForce is not None:
            self._check(dhd.dhdSetMaxForce(self.info.max_force_n, DHD_DEVICE_ID), "set max force")
        steps = max(1, min(255, round(self.watchdog_s / 125e-6)))
        if dhd.dhdSetWatchdog(steps, DHD_DEVICE_ID) < 0:
            if dhd.dhdEnableExpertMode is None:
                raise DeviceNotFoundError(
                    f"{self.name}: cannot set its watchdog: {dhd.last_error()}"
                )
            dhd.dhdEnableExpertMode()
            try:
                if dhd.dhdSetWatchdog(steps, DHD_DEVICE_ID) < 0:
                    raise DeviceNotFoundError(
                        f"{self.name}: cannot set its watchdog: {dhd.last_error()}"
                    )
            finally:
                if dhd.dhdDisableExpertMode is not None:
                    dhd.dhdDisableExpertMode()
        self._check(dhd.dhdSetForceAndTorque(0, 0, 0, 0, 0, 0, DHD_DEVICE_ID), "zero force")
        self._live = False

    def _go_live(self, dhd: DHDLibrary) -> None:
        """Forces on and brakes off (at the first write)."""
        if (
            dhd.dhdEnableForce(DHD_ON, DHD_DEVICE_ID) < 0
            or dhd.dhdSetBrakes(DHD_OFF, DHD_DEVICE_ID) < 0
        ):
            raise DeviceError(f"{self.name}: cannot enable forces: {dhd.last_error()}")
        self._live = True

    def _check(self, code: int, what: str) -> None:
        if code < 0 and self.dhd is not None:
            raise DeviceNotFoundError(f"{self.name}: cannot {what}: {self.dhd.last_error()}")

    def read(self) -> DeviceState:
        dhd = self.dhd
        if dhd is None:
            raise DeviceError(f"{self.name} is not open")
        if dhd.dhdGetPosition(self._px, self._py, self._pz, DHD_DEVICE_ID) < 0:
            raise DeviceError(f"{self.name}: {dhd.last_error()}")
        p = DHD_AXES.to_ours((self._px.value, self._py.value, self._pz.value))
        c = self.centre_m
        pos = [p[0] - c[0], p[1] - c[1], p[2] - c[2]]
        if not all(map(math.isfinite, pos)):
            raise DeviceError(f"{self.name} reported a non-finite position")
        q = np.array([1.0, 0.0, 0.0, 0.0])
        if self._wrist:
            if dhd.dhdGetOrientationFrame(ctypes.byref(self._frame), DHD_DEVICE_ID) < 0:
                raise DeviceError(f"{self.name}: {dhd.last_error()}")
            r = np.array(self._frame[:]).reshape(3, 3)
            q = quat_from_matrix(DHD_AXES.rotation_to_ours(r))
        buttons = int(dhd.dhdGetButtonMask(DHD_DEVICE_ID))
        return DeviceState(self.time_source(), np.array(pos), q, 0.0, buttons)

    def write(self, force_n: np.ndarray, torque_nm: np.ndarray) -> None:
        dhd = self.dhd
        if dhd is None:
            raise DeviceError(f"{self.name} is not open")
        info = self.info
        f = DHD_AXES.to_device(limited([float(v) for v in force_n], info.max_force_n))
        t = [0.0, 0.0, 0.0]
        if self._torque:
            t = DHD_AXES.to_device(limited([float(v) for v in torque_nm], info.max_torque_nm))
        code = dhd.dhdSetForceAndTorque(f[0], f[1], f[2], t[0], t[1], t[2], DHD_DEVICE_ID)
        if code < 0:
            raise DeviceError(f"{self.name}: {dhd.last_error()}")
        if not self._live:
            self._go_live(dhd)

    def close(self) -> None:
        self._shutdown()

    def _shutdown(self) -> None:
        dhd, self.dhd = self.dhd, None
        if dhd is None:
            return
        # each step is tried even if the one before failed (an unplugged device fails them all)
        dhd.dhdSetForceAndTorque(0, 0, 0, 0, 0, 0, DHD_DEVICE_ID)
        dhd.dhdEnableForce(DHD_OFF, DHD_DEVICE_ID)
        dhd.dhdSetBrakes(DHD_ON, DHD_DEVICE_ID)
        dhd.dhdClose(DHD_DEVICE_ID)
