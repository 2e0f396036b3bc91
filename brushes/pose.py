"""Stylus sample -> brush tip pose (position, orientation, velocities, contact, press depth).

A pen tablet (``input_kind="tablet"``) gives a 2D position, pressure and tilt: pressure sets how
far the tip's lowest point presses below the paint surface (``preset.pressure.depth_for``). A
haptic device (``input_kind="haptic"``) gives a 3D position: its z is the height of the tip's
lowest point directly. So a tablet sample at pressure p and a haptic sample at
``z = surface - depth_for(p)`` give the same :class:`TipPose`.

In both cases the apex is placed at the sample's (x, y), the tip is oriented by tilt and twist,
and lowered until its lowest point reaches the commanded height; the canvas (z = 0) is rigid, so a
command below it leaves the tip resting on the canvas and counts as ``compression_m``. Pressing
deeper splays the bristles (``preset.splay_for_depth``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Literal, get_args

import numpy as np

from brushes.presets import BrushPreset, TiltResponse
from brushes.stylus import StylusSample
from brushes.tips import lowest_point_z
from common.tilt import (
    angular_velocity,
    axis_from_tilt,
    quat_from_axis_angle,
    quat_multiply,
    quat_to_matrix,
    quat_z_to,
)

InputKind = Literal["tablet", "haptic"]
INPUT_KINDS: tuple[InputKind, ...] = get_args(InputKind)
MIN_DT_S = 1e-6


@dataclass(frozen=True)
class TipPose:
    """Where the brush tip is and how it moves, in the canvas frame.

    Attributes:
        t_s: time (s).
        position_m: (3,) the apex (body origin) in the canvas frame (m).
        orientation: (4,) unit quaternion [w, x, y, z], body -> canvas frame.
        velocity_m_s: (3,) apex velocity (m/s).
        angular_velocity_rad_s: (3,) angular velocity about the apex, canvas frame (rad/s).
        in_contact: the stylus commands the tip below the paint surface (pressure > 0).
        press_depth_m: how far the tip's lowest point sits below the paint surface (m, >= 0).
        pressure: effective pressure 0..1 (from the stylus, or from a haptic device's depth).
        splay: lateral widening factor of the tip (>= 1).
        compression_m: how far the stylus commands past the rigid canvas (m, >= 0).
    """

    t_s: float
    position_m: np.ndarray
    orientation: np.ndarray
    velocity_m_s: np.ndarray
    angular_velocity_rad_s: np.ndarray
    in_contact: bool
    press_depth_m: float
    pressure: float
    splay: float
    compression_m: float

    @property
    def rotation(self) -> np.ndarray:
        """(3, 3) rotation matrix body -> canvas frame."""
        return quat_to_matrix(self.orientation)

    @property
    def axis(self) -> np.ndarray:
        """(3,) unit brush axis (apex toward handle) in the canvas frame."""
        return self.rotation[:, 2]


def orientation_from_tilt(tilt_rad: np.ndarray, twist_rad: float, tilt: TiltResponse) -> np.ndarray:
    """Tip orientation quaternion (4,) from stylus tilt (2,) and twist (rad) through ``tilt``.

    The axis leans in the stylus's direction by ``gain`` times the stylus's angle from the canvas
    normal, at most ``max_rad``; then the tip turns by ``twist_gain * twist_rad`` about its axis.
    """
    stylus_axis = axis_from_tilt(tilt_rad)
    polar = math.acos(min(1.0, float(stylus_axis[2])))
    azimuth = math.atan2(float(stylus_axis[1]), float(stylus_axis[0]))
    lean = min(tilt.gain * polar, tilt.max_rad)
    axis = np.array(
        [math.sin(lean) * math.cos(azimuth), math.sin(lean) * math.sin(azimuth), math.cos(lean)]
    )
    twist = quat_from_axis_angle(np.array([0.0, 0.0, 1.0]), tilt.twist_gain * twist_rad)
    return quat_multiply(quat_z_to(axis), twist)


def place_tip(
    sample: StylusSample,
    preset: BrushPreset,
    input_kind: InputKind = "tablet",
    surface_z_m: float = 0.0,
) -> TipPose:
    """The tip pose for one sample, with zero velocities (see :class:`TipTracker` for those).

    ``surface_z_m`` is the paint surface height (m, >= 0) under the tip: 0 on a bare canvas.
    """
    if input_kind not in INPUT_KINDS:
        raise ValueError(f"input_kind must be one of {INPUT_KINDS}, got {input_kind!r}")
    if not (math.isfinite(surface_z_m) and surface_z_m >= 0.0):
        raise ValueError(f"surface_z_m must be finite and >= 0, got {surface_z_m}")
    if input_kind == "tablet":
        low_cmd_m = surface_z_m - preset.pressure.depth_for(sample.pressure)
    else:
        low_cmd_m = float(sample.position_m[2])
    depth_cmd_m = surface_z_m - low_cmd_m
    splay = preset.splay_for_depth(depth_cmd_m)
    q = orientation_from_tilt(sample.tilt_rad, sample.twist_rad, preset.tilt)
    low_offset_m = lowest_point_z(preset.tip(splay), quat_to_matrix(q))
    low_m = max(low_cmd_m, 0.0)
    position = np.array([sample.position_m[0], sample.position_m[1], low_m - low_offset_m])
    zero = np.zeros(3)
    return TipPose(
        t_s=sample.t_s,
        position_m=position,
        orientation=q,
        velocity_m_s=zero,
        angular_velocity_rad_s=zero.copy(),
        in_contact=depth_cmd_m > 0.0,
        press_depth_m=max(surface_z_m - low_m, 0.0),
        pressure=preset.pressure.pressure_for(depth_cmd_m),
        splay=splay,
        compression_m=low_m - low_cmd_m,
    )


def _clamp_norm(v: np.ndarray, limit: float) -> tuple[np.ndarray, bool]:
    norm = float(np.linalg.norm(v))
    if norm > limit:
        return v * (limit / norm), True
    return v, False


class TipTracker:
    """Turns a stream of stylus samples into tip poses with finite-difference velocities.

    Velocities come from consecutive poses. A repeated timestamp (dt below 1 microsecond) keeps
    the previous velocities; time running backwards restarts the estimate at zero. Speeds above
    ``max_speed_m_s`` / ``max_angular_speed_rad_s`` (a stylus lifted and put down elsewhere) are
    clamped to those limits and counted in ``jumps``. ``smoothing_s`` > 0 low-pass filters the
    velocities with that time constant (s).

    ``preset`` may be reassigned between samples (switching brushes).
    """

    def __init__(
        self,
        preset: BrushPreset,
        input_kind: InputKind = "tablet",
        *,
        max_speed_m_s: float = 2.0,
        max_angular_speed_rad_s: float = 40.0,
        smoothing_s: float = 0.0,
    ) -> None:
        if input_kind not in INPUT_KINDS:
            raise ValueError(f"input_kind must be one of {INPUT_KINDS}, got {input_kind!r}")
        if not (max_speed_m_s > 0.0 and max_angular_speed_rad_s > 0.0 and smoothing_s >= 0.0):
            raise ValueError("speed limits must be positive and smoothing_s >= 0")
        self.preset = preset
        self.input_kind: InputKind = input_kind
        self.max_speed_m_s = max_speed_m_s
        self.max_angular_speed_rad_s = max_angular_speed_rad_s
        self.smoothing_s = smoothing_s
        self.jumps = 0
        self.last: TipPose | None = None

    def reset(self) -> None:
        """Forget the previous pose: the next sample starts at zero velocity."""
        self.last = None

    def update(self, sample: StylusSample, surface_z_m: float = 0.0) -> TipPose:
        """The pose for ``sample`` (paint surface at ``surface_z_m`` under the tip)."""
        pose = place_tip(sample, self.preset, self.input_kind, surface_z_m)
        prev, self.last = self.last, pose
        if prev is None or pose.t_s < prev.t_s:
            return pose
        dt = pose.t_s - prev.t_s
        if dt < MIN_DT_S:
            pose = replace(
                pose,
                velocity_m_s=prev.velocity_m_s,
                angular_velocity_rad_s=prev.angular_velocity_rad_s,
            )
            self.last = pose
            return pose
        v, jump_v = _clamp_norm((pose.position_m - prev.position_m) / dt, self.max_speed_m_s)
        w = angular_velocity(prev.orientation, pose.orientation, dt)
        w, jump_w = _clamp_norm(w, self.max_angular_speed_rad_s)
        self.jumps += int(jump_v or jump_w)
        if self.smoothing_s > 0.0:
            alpha = dt / (self.smoothing_s + dt)
            v = prev.velocity_m_s + alpha * (v - prev.velocity_m_s)
            w = prev.angular_velocity_rad_s + alpha * (w - prev.angular_velocity_rad_s)
        pose = replace(pose, velocity_m_s=v, angular_velocity_rad_s=w)
        self.last = pose
        return pose
