"""Rigid canvas contact: a stiff spring-damper that holds the tip above the canvas plane.

The fluid gives the feel of the paint; the canvas under it must feel solid. When the tip goes
below the canvas plane (height ``height_m`` along +z in the device frame) by a depth ``d``, the
servo loop adds ``F_z = k d - b v_z`` (never pulling: ``F_z >= 0``). The gains are fractions of
the device's own ``max_stiffness_n_per_m`` and ``max_damping_ns_per_m``, the largest values it
renders without going unstable, so the wall is as stiff as the device allows.

On a canvas with tooth (``surface``, :mod:`paintapp.canvas.surfaces`) the wall follows the tooth's
height under the tip, a haptic texture: the plane is at ``height_m + z_t`` with ``z_t`` the
*rendered* tooth height, which is kept stable at the servo rate with the device's stiffness by
three filters, in order:

1. **Spatial**: the tile is low-passed by a Gaussian of ``tooth_blur_m`` (0.1 mm: a stylus tip is
   rounded, it rides over finer grain) when it is built, and sampled bilinearly, periodically,
   at the tip's (x, y) each tick (``tooth_gain`` times the true height).
2. **Along the path**: a one-pole low-pass of cut-off ``tooth_cutoff_hz`` (150 Hz) on the height
   the tip meets, tick by tick: a fast drag over fine grain is felt as a buzz below the cut-off,
   not as steps.
3. **Slope limit**: ``z_t`` moves at most ``dz = tooth_step_fraction * max_force_n / k`` per tick
   (``k`` the wall's stiffness, a fraction of the device's ``max_stiffness_n_per_m``), so the
   tooth changes the wall force by at most ``tooth_step_fraction`` (2 %) of the device's force
   limit per tick: five times under the safety stage's rate limit
   (:class:`paintapp.haptics.safety.SafetyConfig`, the full limit in 10 ticks), which therefore
   never acts on the texture.

The texture moves the plane along z only (no lateral force from the tooth's slopes), and the wall
still never pulls. The tile is built from the surface's name (deterministic, numpy only); a
change of surface (:meth:`CanvasContact.set_surface`) builds the new tile on a thread of its own
and swaps it in, the slope limit easing the wall to the new height.
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass

import numpy as np

from common.errors import InputError
from common.surfaces import SMOOTH, blurred_tile, surface_spec
from paintapp.haptics.device import DeviceInfo


@dataclass(frozen=True)
class ContactConfig:
    """Canvas plane and wall gains.

    Attributes:
        height_m: canvas plane height (z) in the device frame, m.
        stiffness_fraction: wall stiffness as a fraction of the device's maximum.
        damping_fraction: wall damping as a fraction of the device's maximum.
        pressure_depth_m: depth below the canvas at which a haptic device reports full pressure.
        surface: the canvas surface whose tooth the wall follows (``smooth``: a flat plane).
        tooth_gain: the felt tooth height over the true one, [0, 10].
        tooth_blur_m: Gaussian low-pass of the felt tile, m (the stylus tip's rounding).
        tooth_cutoff_hz: cut-off of the low-pass along the path, Hz.
        tooth_step_fraction: the tooth's largest wall force change per tick, as a fraction of the
            device's force limit.
    """

    height_m: float = 0.0
    stiffness_fraction: float = 0.5
    damping_fraction: float = 0.5
    pressure_depth_m: float = 0.004
    surface: str = SMOOTH
    tooth_gain: float = 1.0
    tooth_blur_m: float = 1e-4
    tooth_cutoff_hz: float = 150.0
    tooth_step_fraction: float = 0.02

    def __post_init__(self) -> None:
        if not math.isfinite(self.height_m):
            raise InputError("canvas height must be finite", key="height_m")
        for name in ("stiffness_fraction", "damping_fraction"):
            value = getattr(self, name)
            if not (math.isfinite(value) and 0.0 <= value <= 1.0):
                raise InputError(f"must be in [0, 1], got {value}", key=name)
        if not self.pressure_depth_m > 0:
            raise InputError("pressure depth must be positive", key="pressure_depth_m")
        object.__setattr__(self, "surface", surface_spec(self.surface, key="surface").name)
        limits = {
            "tooth_gain": (0.0, 10.0),
            "tooth_blur_m": (0.0, 0.01),
            "tooth_cutoff_hz": (1.0, 1e4),
            "tooth_step_fraction": (1e-6, 0.1),
        }
        for name, (lo, hi) in limits.items():
            value = getattr(self, name)
            if not (math.isfinite(value) and lo <= value <= hi):
                raise InputError(f"must be in [{lo:g}, {hi:g}], got {value}", key=name)


class ToothTile:
    """The felt tooth of a surface: its tile low-passed (filter 1 of the module docstring), and
    the tile's period; :meth:`height_m` samples it (scalar Python, no allocation)."""

    def __init__(self, surface: str, blur_m: float, gain: float) -> None:
        spec = surface_spec(surface)
        self.surface = spec.name
        self.period_m = spec.tile_mm * 1e-3
        tile = blurred_tile(spec.name, blur_m) * gain
        self.tile = np.ascontiguousarray(tile, dtype=np.float64)
        self.n = self.tile.shape[0]

    def height_m(self, x_m: float, y_m: float) -> float:
        """Bilinear, periodic height of the felt tile at (x, y) metres."""
        n, tile = self.n, self.tile
        u = x_m * n / self.period_m
        v = y_m * n / self.period_m
        i, j = math.floor(u), math.floor(v)
        fu, fv = u - i, v - j
        i, j = i % n, j % n
        i1, j1 = (i + 1) % n, (j + 1) % n
        lo = (1.0 - fu) * tile.item(j, i) + fu * tile.item(j, i1)
        hi = (1.0 - fu) * tile.item(j1, i) + fu * tile.item(j1, i1)
        return (1.0 - fv) * lo + fv * hi


class CanvasContact:
    """Spring-damper force of the canvas plane (and its tooth) on the tip.

    Args:
        info: the device; its stiffness and damping limits set the gains, its force limit the
            tooth's slope limit.
        config: plane height, gain fractions and the surface.
        tick_s: the servo period, s (the tooth's filters run once per :meth:`force`).
    """

    def __init__(
        self, info: DeviceInfo, config: ContactConfig | None = None, tick_s: float = 1e-3
    ) -> None:
        self.config = config or ContactConfig()
        self.stiffness_n_per_m = self.config.stiffness_fraction * info.max_stiffness_n_per_m
        self.damping_ns_per_m = self.config.damping_fraction * info.max_damping_ns_per_m
        cfg = self.config
        #: The one-pole low-pass's gain per tick, and the largest tooth move per tick, m.
        self.tooth_alpha = 1.0 - math.exp(-2.0 * math.pi * cfg.tooth_cutoff_hz * tick_s)
        if self.stiffness_n_per_m > 0.0:
            step = cfg.tooth_step_fraction * info.max_force_n / self.stiffness_n_per_m
        else:
            step = 0.0
        self.tooth_step_m = step
        #: The rendered tooth height under the tip, m (0 on a smooth canvas).
        self.tooth_z_m = 0.0
        self._target_m: float | None = None
        self.tooth: ToothTile | None = None
        if cfg.surface != SMOOTH and step > 0.0:
            self.tooth = ToothTile(cfg.surface, cfg.tooth_blur_m, cfg.tooth_gain)

    @property
    def surface(self) -> str:
        """The surface the wall follows now."""
        return self.tooth.surface if self.tooth is not None else SMOOTH

    def set_surface(self, surface: str, wait: bool = False) -> threading.Thread | None:
        """Follow ``surface`` from now on: its tile is built on a thread of its own (returned;
        joined first when ``wait``) and swapped in when ready; ``smooth`` at once."""
        name = surface_spec(surface, key="surface").name
        if name == SMOOTH or self.tooth_step_m <= 0.0:
            self.tooth = None
            return None
        cfg = self.config

        def build() -> None:
            self.tooth = ToothTile(name, cfg.tooth_blur_m, cfg.tooth_gain)

        thread = threading.Thread(target=build, name="tooth-tile", daemon=True)
        thread.start()
        if wait:
            thread.join()
        return thread

    def follow_tooth(self, position_m: np.ndarray) -> float:
        """Advance the tooth's filters (module docstring) with the tip at ``position_m``; the
        rendered tooth height, m. A non-finite position keeps the last height."""
        tooth = self.tooth
        x, y = float(position_m[0]), float(position_m[1])
        if tooth is None:
            target = 0.0
        elif math.isfinite(x) and math.isfinite(y):
            target = tooth.height_m(x, y)
        else:
            target = self._target_m if self._target_m is not None else self.tooth_z_m
        if self._target_m is None:
            self._target_m = target
        self._target_m += self.tooth_alpha * (target - self._target_m)
        step = self.tooth_step_m
        move = min(max(self._target_m - self.tooth_z_m, -step), step)
        self.tooth_z_m += move
        return self.tooth_z_m

    def depth_m(self, position_m: np.ndarray) -> float:
        """How far the tip is below the canvas surface (the plane plus the rendered tooth), m
        (negative above it)."""
        return self.config.height_m + self.tooth_z_m - float(position_m[2])

    def force(self, position_m: np.ndarray, velocity_m_per_s: np.ndarray) -> np.ndarray:
        """Contact force on the tip, N, shape (3,); zero above the canvas. Called once per
        tick: it advances the tooth's filters."""
        if self.tooth is not None or self.tooth_z_m != 0.0:
            self.follow_tooth(position_m)
        depth = self.depth_m(position_m)
        out = np.zeros(3)
        if depth > 0.0:
            fz = self.stiffness_n_per_m * depth - self.damping_ns_per_m * float(velocity_m_per_s[2])
            out[2] = max(fz, 0.0)
        return out

    def pressure(self, position_m: np.ndarray) -> float:
        """Pressure in [0, 1] a force device reports: depth over ``pressure_depth_m``, clipped."""
        return min(max(self.depth_m(position_m) / self.config.pressure_depth_m, 0.0), 1.0)
