"""What the vendor backends share: finding a vendor's shared library, binding its functions
with :mod:`ctypes`, and mapping a device's axes onto ours.

A library is looked for, in order, at the path an environment variable names (so a user can point
at any install, and the tests at a fake), by the system's loader search
(:func:`ctypes.util.find_library`), and at the vendor's usual install paths. Nothing is loaded
until a backend is opened or probed: importing this module loads no vendor code.

Our frame (:mod:`paintapp.haptics.device`): metres, right-handed, x to the user's right, y away
from the user, z up. An :class:`AxisMap` is a signed permutation of a device's axes (a proper
rotation, so handedness is kept), applied to positions, velocities, forces and torques alike.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import math
import os
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from paintapp.haptics.device import DeviceNotFoundError


@dataclass(frozen=True)
class LibrarySpec:
    """Where a vendor library is looked for.

    Attributes:
        product: what the user installs, for messages ("OpenHaptics (libHD)").
        env_var: environment variable holding the library's path.
        loader_names: names for :func:`ctypes.util.find_library` ("HD" for libHD.so).
        paths: the vendor's usual install paths, tried in order.
        install_hint: one short sentence on what to install.
    """

    product: str
    env_var: str
    loader_names: tuple[str, ...]
    paths: tuple[str, ...]
    install_hint: str

    def install_paths(self) -> list[str]:
        """The vendor's usual paths for this platform, with set variables expanded."""
        windows = sys.platform == "win32"
        return [
            os.path.expandvars(p)
            for p in self.paths
            if p.lower().endswith(".dll") == windows and _env_set(p)
        ]

    def candidates(self) -> list[tuple[str, bool]]:
        """Where to look, in order: (path or loader name, whether it is a file path). An
        environment variable, when set, is the only candidate (an explicit choice: no silent
        fallback elsewhere)."""
        override = os.environ.get(self.env_var, "").strip()
        if override:
            return [(override, os.path.sep in override)]
        found: list[tuple[str, bool]] = []
        for name in self.loader_names:
            path = ctypes.util.find_library(name)
            if path:
                found.append((path, os.path.isabs(path)))
        found.extend((p, True) for p in self.install_paths())
        return found

    def where(self) -> str:
        """A short description of where it looks, for messages."""
        return ", ".join([f"${self.env_var}", "the system library path", *self.install_paths()])

    def not_found(self, detail: str = "") -> str:
        """The one-line message for a missing library."""
        extra = f" ({detail})" if detail else ""
        return (
            f"{self.product} not found{extra}: {self.install_hint} Looked in {self.where()}; "
            f"set {self.env_var}=/path/to/library to use another."
        )


def _env_set(path: str) -> bool:
    """Whether every ``$NAME`` in ``path`` is set."""
    return "$" not in os.path.expandvars(path)


def locate(spec: LibrarySpec) -> str | None:
    """The first candidate path that exists (or a bare loader name), without loading it."""
    for path, is_file in spec.candidates():
        if not is_file or os.path.exists(path):
            return path
    return None


def load_library(spec: LibrarySpec) -> ctypes.CDLL:
    """Load the library ``spec`` describes.

    Raises:
        DeviceNotFoundError: it is not installed or cannot be loaded, with what to install.
    """
    path = locate(spec)
    if path is None:
        override = os.environ.get(spec.env_var, "").strip()
        detail = f"{spec.env_var}={override} does not exist" if override else ""
        raise DeviceNotFoundError(spec.not_found(detail))
    try:
        return ctypes.CDLL(path)
    except OSError as exc:
        raise DeviceNotFoundError(spec.not_found(f"{path} does not load: {exc}")) from exc


def bind(
    lib: ctypes.CDLL, spec: LibrarySpec, name: str, restype: object, argtypes: Sequence[object]
) -> Any:
    """Look up ``name`` in ``lib`` and set its signature.

    Raises:
        DeviceNotFoundError: the library lacks the function (too old, or not the vendor's).
    """
    try:
        func = getattr(lib, name)
    except AttributeError as exc:
        raise DeviceNotFoundError(
            f"{spec.product}: the library {getattr(lib, '_name', '?')} has no {name}() "
            f"(an older or different library); {spec.install_hint}"
        ) from exc
    func.restype = restype
    func.argtypes = list(argtypes)
    return func


@dataclass(frozen=True)
class AxisMap:
    """Our axis i is ``signs[i] * device axis axes[i]`` (a signed permutation, determinant +1).

    Attributes:
        axes: which device axis each of our x, y, z is.
        signs: +1 or -1 per our axis.
    """

    axes: tuple[int, int, int]
    signs: tuple[float, float, float]

    def __post_init__(self) -> None:
        if sorted(self.axes) != [0, 1, 2] or any(s not in (1.0, -1.0) for s in self.signs):
            raise ValueError(f"not a signed permutation: {self.axes}, {self.signs}")
        if abs(np.linalg.det(self.matrix) - 1.0) > 1e-9:
            raise ValueError("an axis map must keep handedness (determinant +1)")

    @property
    def matrix(self) -> np.ndarray:
        """The rotation R with ours = R @ device, shape (3, 3)."""
        m = np.zeros((3, 3))
        for i, (a, s) in enumerate(zip(self.axes, self.signs, strict=True)):
            m[i, a] = s
        return m

    def to_ours(self, v: Sequence[float], scale: float = 1.0) -> list[float]:
        """A device vector in our axes, times ``scale`` (plain floats: cheap per tick)."""
        a, s = self.axes, self.signs
        return [s[0] * v[a[0]] * scale, s[1] * v[a[1]] * scale, s[2] * v[a[2]] * scale]

    def to_device(self, v: Sequence[float], scale: float = 1.0) -> list[float]:
        """One of our vectors in the device's axes, times ``scale``."""
        out = [0.0, 0.0, 0.0]
        for i in range(3):
            out[self.axes[i]] = self.signs[i] * float(v[i]) * scale
        return out

    def rotation_to_ours(self, r_device: np.ndarray) -> np.ndarray:
        """A device-frame rotation matrix expressed in our frame: ``R r R^T``."""
        m = self.matrix
        return m @ r_device @ m.T


def quat_from_matrix(r: np.ndarray) -> np.ndarray:
    """Unit quaternion (w, x, y, z), w >= 0, of a rotation matrix; identity if ``r`` is not a
    finite rotation (a device reporting garbage must not stop the loop: the position still
    counts)."""
    r = np.asarray(r, dtype=np.float64)
    if r.shape != (3, 3) or not np.all(np.isfinite(r)):
        return np.array([1.0, 0.0, 0.0, 0.0])
    if float(np.max(np.abs(r @ r.T - np.eye(3)))) > 1e-3 or np.linalg.det(r) < 0:
        return np.array([1.0, 0.0, 0.0, 0.0])  # not a rotation
    trace = float(r[0, 0] + r[1, 1] + r[2, 2])
    if trace > 0.0:
        s = 2.0 * math.sqrt(trace + 1.0)
        q = [0.25 * s, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s]
    else:
        i = int(np.argmax(np.diag(r)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * math.sqrt(max(1.0 + r[i, i] - r[j, j] - r[k, k], 1e-12))
        q = [0.0, 0.0, 0.0, 0.0]
        q[0] = (r[k, j] - r[j, k]) / s
        q[1 + i] = 0.25 * s
        q[1 + j] = (r[j, i] + r[i, j]) / s
        q[1 + k] = (r[k, i] + r[i, k]) / s
    out = np.array(q)
    n = float(np.linalg.norm(out))
    if not math.isfinite(n) or n < 1e-9:
        return np.array([1.0, 0.0, 0.0, 0.0])
    out /= n
    return out if out[0] >= 0 else -out


def finite3(v: Sequence[float]) -> bool:
    """Whether all three components are finite."""
    return math.isfinite(v[0]) and math.isfinite(v[1]) and math.isfinite(v[2])


def limited(v: list[float], limit: float) -> list[float]:
    """``v`` (3 floats) with non-finite values zeroed and its magnitude clamped to ``limit``."""
    if not finite3(v):
        return [0.0, 0.0, 0.0]
    n = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    if n > limit:
        s = limit / n if n > 0 else 0.0
        return [v[0] * s, v[1] * s, v[2] * s]
    return v
