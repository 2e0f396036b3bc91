"""3D Systems Touch, Touch X and Phantom devices through the OpenHaptics HD API (``libHD``), as a
:class:`~paintapp.haptics.device.HapticDevice`; bound with :mod:`ctypes` when opened.

Forces reach the motors only while the HD scheduler runs, so :meth:`OpenHapticsDevice.open`
schedules one 1 kHz callback that reads the stylus into a buffer and writes the latest commanded
force; :meth:`~OpenHapticsDevice.read` and :meth:`~OpenHapticsDevice.write` only swap buffers.

Frame and units: the HD frame is x right, y up, z toward the user, in mm, N and mN m; ours
(:mod:`paintapp.haptics.device`) is x right, y away from the user, z up, in m, N and N m. So ours
= (x, -z, y) / 1000 for positions, (x, -z, y) for forces, torques the same axes over 1000, and
the orientation turned likewise. Limits (force, stiffness, workspace, torque) come from the device.

Safety: the device's own force clamping, ramping and software limits are enabled at open; a force
not refreshed for :data:`HOLD_FRAMES` ticks drops to zero; an HD error stops the callback with zero
force and the next read raises :class:`~paintapp.haptics.device.DeviceError`.

Setup: docs/guide/devices-vendor.md.
"""

from __future__ import annotations

import ctypes
import math
import threading
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

HD_SPEC = LibrarySpec(
    product="OpenHaptics (libHD)",
    env_var="PAINTAPP_LIBHD",
    loader_names=("HD",),
    paths=(
        "/usr/lib/libHD.so",
        "/usr/lib64/libHD.so",
        "/usr/local/lib/libHD.so",
        "$OH_SDK_BASE/lib/libHD.so",
        "C:\\Windows\\System32\\hd.dll",
    ),
    install_hint="install 3D Systems' OpenHaptics (Developer Edition) and the Touch device driver.",
)

# hdDefines.h
HD_SUCCESS = 0x0000
HD_CURRENT_BUTTONS = 0x2000
HD_CURRENT_POSITION = 0x2050
HD_CURRENT_TRANSFORM = 0x2052
HD_DEVICE_MODEL_TYPE = 0x2501
HD_USABLE_WORKSPACE_DIMENSIONS = 0x2551
HD_INPUT_DOF = 0x2553
HD_OUTPUT_DOF = 0x2554
HD_NOMINAL_MAX_STIFFNESS = 0x2602
HD_NOMINAL_MAX_FORCE = 0x2603
HD_NOMINAL_MAX_CONTINUOUS_FORCE = 0x2604
HD_SOFTWARE_VELOCITY_LIMIT = 0x2606
HD_SOFTWARE_FORCE_IMPULSE_LIMIT = 0x2607
HD_NOMINAL_MAX_DAMPING = 0x2609
HD_NOMINAL_MAX_TORQUE_CONTINUOUS_FORCE = 0x2623
HD_CURRENT_FORCE = 0x2700
HD_CURRENT_TORQUE = 0x2701
HD_FORCE_OUTPUT = 0x4000
HD_MAX_FORCE_CLAMPING = 0x4001
HD_FORCE_RAMPING = 0x4002
HD_SOFTWARE_FORCE_LIMIT = 0x4003
HD_INVALID_HANDLE = 0xFFFFFFFF
HD_CALLBACK_DONE = 0
HD_CALLBACK_CONTINUE = 1
HD_MAX_SCHEDULER_PRIORITY = 0xFFFF

#: The device's own safety switches, enabled at open.
SAFETY_CAPABILITIES = (
    HD_FORCE_OUTPUT,
    HD_MAX_FORCE_CLAMPING,
    HD_FORCE_RAMPING,
    HD_SOFTWARE_FORCE_LIMIT,
    HD_SOFTWARE_FORCE_IMPULSE_LIMIT,
    HD_SOFTWARE_VELOCITY_LIMIT,
)
#: Scheduler ticks a force is held without a fresh write from the servo loop.
HOLD_FRAMES = 20
#: HD axes -> ours: (x, -z, y).
HD_AXES = AxisMap(axes=(0, 2, 1), signs=(1.0, -1.0, 1.0))


class HDErrorInfo(ctypes.Structure):
    """``HDErrorInfo``: the error code, the device's internal code and the device handle."""

    _fields_ = [
        ("errorCode", ctypes.c_uint),
        ("internalErrorCode", ctypes.c_int),
        ("hHD", ctypes.c_uint),
    ]


SchedulerCallback = ctypes.CFUNCTYPE(ctypes.c_uint, ctypes.c_void_p)


class HDLibrary:
    """The subset of ``libHD`` the backend calls, with signatures set."""

    def __getattr__(self, name: str) -> Any:
        """The bound C functions are set per instance in ``__init__``; this only types them."""
        raise AttributeError(name)

    def __init__(self, lib: ctypes.CDLL) -> None:
        d, u, i, v = ctypes.c_double, ctypes.c_uint, ctypes.c_int, None
        dp, ip, s = ctypes.POINTER(d), ctypes.POINTER(i), ctypes.c_char_p
        self.lib = lib
        sig: dict[str, tuple[object, list[object]]] = {
            "hdInitDevice": (u, [s]),
            "hdDisableDevice": (v, [u]),
            "hdMakeCurrentDevice": (v, [u]),
            "hdGetError": (HDErrorInfo, []),
            "hdGetErrorString": (s, [u]),
            "hdEnable": (v, [u]),
            "hdBeginFrame": (v, [u]),
            "hdEndFrame": (v, [u]),
            "hdGetDoublev": (v, [u, dp]),
            "hdGetIntegerv": (v, [u, ip]),
            "hdGetString": (s, [u]),
            "hdSetDoublev": (v, [u, dp]),
            "hdStartScheduler": (v, []),
            "hdStopScheduler": (v, []),
            "hdScheduleAsynchronous": (
                ctypes.c_ulong,
                [SchedulerCallback, ctypes.c_void_p, ctypes.c_ushort],
            ),
            "hdUnschedule": (v, [ctypes.c_ulong]),
        }
        for name, (restype, argtypes) in sig.items():
            setattr(self, name, bind(lib, HD_SPEC, name, restype, argtypes))

    def drain(self) -> None:
        """Pop every queued HD error (stale ones from an earlier session or a shutdown)."""
        for _ in range(64):
            if self.hdGetError().errorCode == HD_SUCCESS:
                return

    def error(self) -> str | None:
        """The pending HD error as text, or None."""
        info = self.hdGetError()
        if info.errorCode == HD_SUCCESS:
            return None
        raw = self.hdGetErrorString(info.errorCode)
        text = raw.decode(errors="replace") if raw else "unknown error"
        return f"{text} (HD error 0x{info.errorCode:04x}, device code {info.internalErrorCode})"


def load_hd() -> HDLibrary:
    """Load and bind ``libHD`` (:class:`DeviceNotFoundError` with what to install if missing)."""
    return HDLibrary(load_library(HD_SPEC))


class OpenHapticsDevice:
    """An OpenHaptics device as a :class:`HapticDevice`.

    Args:
        time_source: the servo clock's ``now_s``; readings are stamped with it.
        config_name: the device's name in the Touch Setup utility; None: the default device.
        centre_m: our origin in our frame relative to the device origin, m.
    """

    def __init__(
        self,
        time_source: Callable[[], float] = time.perf_counter,
        config_name: str | None = None,
        centre_m: tuple[float, float, float] = (0.0, 0.0, 0.0),
    ) -> None:
        self.time_source = time_source
        self.config_name = config_name
        self.centre_m = tuple(float(c) for c in centre_m)
        self.hd: HDLibrary | None = None
        self._handle = HD_INVALID_HANDLE
        self._info: DeviceInfo | None = None
        self._callback = SchedulerCallback(self._frame)
        self._task: int | None = None
        self._lock = threading.Lock()
        self._pos = (ctypes.c_double * 3)()
        self._xf = (ctypes.c_double * 16)()
        self._buttons = ctypes.c_int(0)
        self._out_f = (ctypes.c_double * 3)()
        self._out_t = (ctypes.c_double * 3)()
        # position mm (3), rotation row by row (9), buttons
        self._state = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        self._frames = 0
        self._force_dev = [0.0, 0.0, 0.0]
        self._torque_dev = [0.0, 0.0, 0.0]
        self._since_write = 0
        self._closing = False
        self._fault: str | None = None
        self._torque = False

    @property
    def info(self) -> DeviceInfo:
        if self._info is None:
            raise DeviceError("OpenHaptics device is not open")
        return self._info

    @property
    def name(self) -> str:
        return f"OpenHaptics device {self.config_name or '(default)'}"

    def open(self) -> None:
        hd = load_hd()
        hd.drain()
        name = self.config_name.encode() if self.config_name else None
        handle = hd.hdInitDevice(name)
        err = hd.error()
        if err is not None or handle == HD_INVALID_HANDLE:
            raise DeviceNotFoundError(
                f"{self.name} did not initialise: {err or 'invalid handle'} (is it plugged in, "
                "powered and configured in Touch Setup?)"
            )
        self.hd, self._handle = hd, handle
        try:
            hd.hdMakeCurrentDevice(handle)
            self._info = self._read_info(hd)
            for cap in SAFETY_CAPABILITIES:
                hd.hdEnable(cap)
                err = hd.error()
                if err is not None and cap in (HD_FORCE_OUTPUT, HD_MAX_FORCE_CLAMPING):
                    raise DeviceNotFoundError(f"{self.name}: cannot enable force output: {err}")
            self._closing, self._fault, self._since_write = False, None, 0
            self._task = hd.hdScheduleAsynchronous(self._callback, None, HD_MAX_SCHEDULER_PRIORITY)
            hd.hdStartScheduler()
            err = hd.error()
            if err is not None:
                raise DeviceNotFoundError(f"{self.name}: the HD scheduler did not start: {err}")
        except BaseException:
            self._shutdown()
            raise

    def _get_doubles(self, hd: HDLibrary, pname: int, n: int) -> list[float]:
        buf = (ctypes.c_double * n)()
        hd.hdGetDoublev(pname, buf)
        return [float(x) for x in buf] if hd.error() is None else [math.nan] * n

    def _get_int(self, hd: HDLibrary, pname: int) -> int | None:
        value = ctypes.c_int(0)
        hd.hdGetIntegerv(pname, ctypes.byref(value))
        return int(value.value) if hd.error() is None else None

    def _read_info(self, hd: HDLibrary) -> DeviceInfo:
        raw = hd.hdGetString(HD_DEVICE_MODEL_TYPE)
        hd.error()
        model = raw.decode(errors="replace") if raw else "OpenHaptics device"
        cont = self._get_doubles(hd, HD_NOMINAL_MAX_CONTINUOUS_FORCE, 1)[0]
        peak = self._get_doubles(hd, HD_NOMINAL_MAX_FORCE, 1)[0]
        force = cont if math.isfinite(cont) and cont > 0 else peak
        if not (math.isfinite(force) and force > 0):
            raise DeviceNotFoundError(f"{self.name} reports no maximum force; refusing to drive it")
        stiff = self._get_doubles(hd, HD_NOMINAL_MAX_STIFFNESS, 1)[0] * 1000.0
        damp = self._get_doubles(hd, HD_NOMINAL_MAX_DAMPING, 1)[0] * 1000.0
        box = self._get_doubles(hd, HD_USABLE_WORKSPACE_DIMENSIONS, 6)
        extent_dev = [abs(box[3 + i] - box[i]) * 1e-3 for i in range(3)]
        extent = [abs(e) for e in HD_AXES.to_ours(extent_dev)]
        inputs = self._get_int(hd, HD_INPUT_DOF) or 3
        outputs = self._get_int(hd, HD_OUTPUT_DOF) or 3
        torque = 0.0
        if outputs >= 6:
            torque = self._get_doubles(hd, HD_NOMINAL_MAX_TORQUE_CONTINUOUS_FORCE, 1)[0] * 1e-3
            torque = torque if math.isfinite(torque) and torque > 0 else 0.0
        self._torque = torque > 0
        return DeviceInfo(
            name=model,
            kind="openhaptics",
            dof_sensed=6 if inputs >= 6 else 3,
            dof_actuated=6 if self._torque else 3,
            max_force_n=force,
            max_torque_nm=torque,
            max_stiffness_n_per_m=stiff if math.isfinite(stiff) and stiff > 0 else 0.0,
            max_damping_ns_per_m=damp if math.isfinite(damp) and damp > 0 else 0.0,
            workspace_m=(extent[0], extent[1], extent[2])
            if all(map(math.isfinite, extent))
            else (0.0, 0.0, 0.0),
        )

    def _frame(self, _data: object) -> int:
        """The scheduler's callback: one haptic frame (runs in the HD scheduler's thread)."""
        hd = self.hd
        if hd is None:
            return HD_CALLBACK_DONE
        try:
            hd.hdBeginFrame(self._handle)
            hd.hdGetDoublev(HD_CURRENT_POSITION, self._pos)
            hd.hdGetDoublev(HD_CURRENT_TRANSFORM, self._xf)
            hd.hdGetIntegerv(HD_CURRENT_BUTTONS, ctypes.byref(self._buttons))
            with self._lock:
                self._since_write += 1
                hold = not self._closing and self._since_write <= HOLD_FRAMES
                f = self._force_dev if hold else (0.0, 0.0, 0.0)
                t = self._torque_dev if hold else (0.0, 0.0, 0.0)
                self._out_f[0], self._out_f[1], self._out_f[2] = f
                self._out_t[0], self._out_t[1], self._out_t[2] = t
            hd.hdSetDoublev(HD_CURRENT_FORCE, self._out_f)
            if self._torque:
                hd.hdSetDoublev(HD_CURRENT_TORQUE, self._out_t)
            hd.hdEndFrame(self._handle)
            err = hd.error()
            if err is not None:
                self._fault = err
                self._zero_frame(hd)
                return HD_CALLBACK_DONE
            x = self._xf
            with self._lock:
                self._state[0:3] = self._pos[0:3]
                # HD_CURRENT_TRANSFORM is column-major: rotation row r is x[r], x[4 + r], x[8 + r]
                self._state[3:12] = [x[0], x[4], x[8], x[1], x[5], x[9], x[2], x[6], x[10]]
                self._state[12] = float(self._buttons.value)
                self._frames += 1
            return HD_CALLBACK_DONE if self._closing else HD_CALLBACK_CONTINUE
        except Exception as exc:  # nothing may escape into the vendor's thread
            self._fault = f"{type(exc).__name__}: {exc}"
            return HD_CALLBACK_DONE

    def _zero_frame(self, hd: HDLibrary) -> None:
        """One more frame writing zero force (after an error), errors ignored."""
        zero = (ctypes.c_double * 3)()
        hd.hdBeginFrame(self._handle)
        hd.hdSetDoublev(HD_CURRENT_FORCE, zero)
        if self._torque:
            hd.hdSetDoublev(HD_CURRENT_TORQUE, zero)
        hd.hdEndFrame(self._handle)
        hd.error()

    def read(self) -> DeviceState:
        if self.hd is None:
            raise DeviceError(f"{self.name} is not open")
        if self._fault is not None:
            raise DeviceError(f"{self.name}: {self._fault}")
        with self._lock:
            s = list(self._state)
        pos = HD_AXES.to_ours(s[0:3], 1e-3)
        pos = [pos[0] - self.centre_m[0], pos[1] - self.centre_m[1], pos[2] - self.centre_m[2]]
        if not all(map(math.isfinite, pos)):
            raise DeviceError(f"{self.name} reported a non-finite position")
        rot = HD_AXES.rotation_to_ours(np.array(s[3:12]).reshape(3, 3))
        q = quat_from_matrix(rot)
        return DeviceState(self.time_source(), np.array(pos), q, 0.0, int(s[12]))

    def write(self, force_n: np.ndarray, torque_nm: np.ndarray) -> None:
        if self.hd is None:
            raise DeviceError(f"{self.name} is not open")
        if self._fault is not None:
            raise DeviceError(f"{self.name}: {self._fault}")
        info = self.info
        f = limited([float(v) for v in force_n], info.max_force_n)
        t = limited([float(v) for v in torque_nm], info.max_torque_nm)
        fd = HD_AXES.to_device(f)
        td = HD_AXES.to_device(t, 1e3)  # N m -> mN m
        with self._lock:
            self._force_dev, self._torque_dev = fd, td
            self._since_write = 0

    def close(self) -> None:
        if self.hd is None:
            return
        with self._lock:
            self._force_dev = self._torque_dev = [0.0, 0.0, 0.0]
            self._closing = True
        self._shutdown()

    def _shutdown(self) -> None:
        hd, self.hd = self.hd, None
        if hd is None:
            return
        hd.hdStopScheduler()
        if self._task is not None:
            hd.hdUnschedule(self._task)
            self._task = None
        self._zero_frame(hd)  # the scheduler is stopped: this frame is the last word
        hd.hdDisableDevice(self._handle)
        hd.drain()
        self._handle = HD_INVALID_HANDLE

    @property
    def frames(self) -> int:
        """Scheduler frames run since open."""
        return self._frames
