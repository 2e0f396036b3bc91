"""Feeling a stored flow: a rigid probe in a :class:`~solver.sampled.flow.SampledFlow`, its
force and torque published for the servo loop, and the scripted form that writes a force trace.

The probe is one-way: it reads the flow and does not change it. Its force is the stress integral
of the stored fields over its exact surface (:func:`solver.sampled.forces.surface_force`). In 2D the
force is per unit depth; the probe stands for a body ``depth_m`` deep, so the hand feels
``depth_m`` times it (N); on a 2D mesh one cell thick (a CFD code's 2D case) the depth defaults to
the mesh's thickness, so that the force compares with the one the code reports. The device's frame maps onto the data set's by a scale and an offset
(:class:`Workspace`); a scripted path is already in the data set's frame.

On an unstructured mesh (:class:`~paintapp.explore.unstructured.UnstructuredFlow`) the force is
taken on a local uniform grid resampled around the probe (:mod:`.local_resample`): resampled
right away in scripted runs, on a worker thread in the window (never in the per-tick path).

Nothing non-finite is published: such a sample (it cannot come from validated data, but the
check is cheap) is dropped and counted, and the servo loop's watchdog fades the force out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from common import quaternion
from common.errors import InputError
from paintapp.explore.local_resample import LocalResampler, ResampleSpec, probe_radius
from paintapp.explore.unstructured import UnstructuredFlow
from paintapp.haptics.channel import ForceChannel
from paintapp.haptics.clock import VirtualClock
from paintapp.haptics.contact import ContactConfig
from paintapp.haptics.devices.stroke_player import ReplayDevice
from paintapp.haptics.servo import ServoConfig, ServoLoop
from solver import Ball, Box, FieldForce, SampledFlow, surface_force, surface_rule

#: A stored flow: on a regular grid, or on an unstructured mesh.
Flow = SampledFlow | UnstructuredFlow

PROBE_SHAPES = ("circle", "box", "sphere")
#: Scripted runs evaluate the force this often (a simulation-like rate; the servo filters it).
DEFAULT_RATE_HZ = 200.0
#: Most force evaluations a scripted run may ask for.
MAX_EVALUATIONS = 2_000_000
#: Longest scripted path, seconds: the servo loop runs one tick per millisecond and keeps every
#: tick's row of the trace, so the duration sets the time and memory a run takes.
MAX_PATH_S = 600.0


@dataclass(frozen=True)
class ProbeSpec:
    """The probe: ``shape`` (circle | box | sphere), ``size_m`` (diameter, or the box's edges)
    and, in 2D, ``depth_m``, how deep a body the per-depth force stands for."""

    shape: str
    size_m: tuple[float, ...]
    depth_m: float | None = None

    def solid(self, dim: int) -> Ball | Box:
        """The solver shape of this probe in a ``dim``-dimensional data set."""
        if self.shape not in PROBE_SHAPES:
            raise InputError(
                f"expected one of {', '.join(PROBE_SHAPES)}, got {self.shape!r}", key="--probe"
            )
        if (self.shape == "sphere") != (dim == 3) and self.shape != "box":
            want = "circle" if dim == 2 else "sphere"
            raise InputError(f"the data set is {dim}D: use a {want} or a box", key="--probe")
        if not all(math.isfinite(s) and s > 0 for s in self.size_m):
            raise InputError(f"expected sizes > 0 (metres), got {self.size_m}", key="--size")
        if self.shape == "box":
            size = self.size_m if len(self.size_m) == dim else self.size_m[:1] * dim
            if len(size) != dim or len(self.size_m) not in (1, dim):
                raise InputError(f"a {dim}D box needs 1 or {dim} sizes", key="--size")
            return Box(tuple(float(s) for s in size))
        if len(self.size_m) != 1:
            raise InputError("a circle or sphere takes one size: its diameter (m)", key="--size")
        return Ball(0.5 * float(self.size_m[0]))

    def felt_depth_m(self, default_m: float | None = None) -> float:
        """2D: the depth the per-depth force is multiplied by (default: ``default_m``, else the
        probe's size)."""
        depth = self.depth_m if self.depth_m is not None else default_m or max(self.size_m)
        if not (math.isfinite(depth) and depth > 0):
            raise InputError(f"expected a depth > 0 (metres), got {depth}", key="--depth")
        return float(depth)


@dataclass(frozen=True)
class Workspace:
    """Device frame -> data frame: ``data = offset_m + scale * device`` (first ``dim`` axes)."""

    offset_m: np.ndarray
    scale: float = 1.0

    def to_data(self, device_m: np.ndarray, dim: int) -> np.ndarray:
        return self.offset_m[:dim] + self.scale * np.asarray(device_m, dtype=float)[:dim]


class Exploration:
    """A probe in a stored flow.

    Args:
        flow: the data set.
        probe: the probe's shape and size.
        quadrature_spacing_m: surface points this far apart (default: half the smallest node
            spacing, so every cell the surface crosses is sampled; on a mesh, half its fine
            cells' size).
        resample: on a mesh, how the local grid is resampled around the probe.
    """

    def __init__(
        self,
        flow: Flow,
        probe: ProbeSpec,
        quadrature_spacing_m: float | None = None,
        resample: ResampleSpec | None = None,
    ) -> None:
        self.flow = flow
        self.probe = probe
        self.shape = probe.solid(flow.dim)
        lo, hi = flow.extent_m
        across = float(np.max(hi - lo))
        if max(probe.size_m) > across:
            raise InputError(
                f"the probe ({max(probe.size_m):g} m) is larger than the data set ({across:g} m "
                "across its longest side): no fluid would be left around it",
                key="--size",
            )
        spacing = quadrature_spacing_m or 0.5 * float(flow.spacing_m.min())
        self.rule = surface_rule(self.shape, flow.dim, spacing)
        thickness = flow.thickness_m if isinstance(flow, UnstructuredFlow) else None
        self.depth_m = probe.felt_depth_m(thickness) if flow.dim == 2 else 1.0
        self.dropped = 0
        self.resampler: LocalResampler | None = None
        if isinstance(flow, UnstructuredFlow):
            radius = probe_radius(self.shape, flow.dim)
            self.resampler = LocalResampler(flow, radius, resample)

    def use_background_resampling(self) -> None:
        """Resample the mesh around the probe on a worker thread from now on (the window)."""
        if self.resampler is not None:
            self.resampler.background = True

    def close(self) -> None:
        """Stop the resampling thread, if any."""
        if self.resampler is not None:
            self.resampler.close()

    def field_at(self, centre_m: np.ndarray) -> SampledFlow:
        """The grid the force at ``centre_m`` is taken on: the flow itself, or on a mesh the
        latest local grid around the probe."""
        if self.resampler is None:
            assert isinstance(self.flow, SampledFlow)
            return self.flow
        return self.resampler.box_for(centre_m).flow

    def force_at(
        self, t_s: float, centre_m: np.ndarray, orientation: np.ndarray | float
    ) -> FieldForce:
        """The flow's force on the probe at ``centre_m`` (dim,) with ``orientation`` (2D angle,
        3D quaternion) at ``t_s``, per unit depth in 2D."""
        rotation = quaternion.rotation_matrix(self.flow.dim, orientation)
        return surface_force(self.field_at(centre_m), self.rule, centre_m, rotation, t_s)

    def felt(self, result: FieldForce) -> tuple[np.ndarray, np.ndarray]:
        """Force (N) and torque (N m) on the hand, both (3,), from a :meth:`force_at` result."""
        if self.flow.dim == 2:
            force = np.array([result.force[0], result.force[1], 0.0]) * self.depth_m
            torque = np.array([0.0, 0.0, float(result.torque)]) * self.depth_m
            return force, torque
        return np.asarray(result.force, dtype=float), np.asarray(result.torque, dtype=float)

    def publish(
        self,
        channel: ForceChannel,
        t_s: float,
        centre_m: np.ndarray,
        orientation: np.ndarray | float,
        data_t_s: float | None = None,
    ) -> FieldForce:
        """Evaluate at the pose and publish the felt force at ``t_s`` (a non-finite one is
        dropped); the flow is read at ``data_t_s`` (default ``t_s``)."""
        result = self.force_at(t_s if data_t_s is None else data_t_s, centre_m, orientation)
        force, torque = self.felt(result)
        if np.all(np.isfinite(force)) and np.all(np.isfinite(torque)):
            channel.publish_force(t_s, force, torque)
        else:
            self.dropped += 1
        return result


def explore_servo_config(force_scale: float) -> ServoConfig:
    """The servo loop's settings for exploring: no canvas (the contact plane far away)."""
    from paintapp.haptics.fluid import FluidConfig

    return ServoConfig(
        fluid=FluidConfig(force_scale=force_scale), contact=ContactConfig(height_m=-1e3)
    )


@dataclass
class ScriptedRun:
    """A scripted exploration: the force trace written to the device each servo tick (ticks, 7:
    time, force xyz N, torque xyz N m), the raw forces at each evaluation (n, 1 + 2 * 3: time,
    felt force, felt torque) and how many evaluations had part of the probe outside the data."""

    trace: np.ndarray
    evaluations: np.ndarray
    outside_evaluations: int


def run_scripted(
    exploration: Exploration,
    path: object,
    *,
    rate_hz: float = DEFAULT_RATE_HZ,
    force_scale: float = 1.0,
    loop: bool = False,
    progress: object = None,
) -> ScriptedRun:
    """Drive the probe along ``path`` (a :class:`~paintapp.explore.probe_paths.ProbePath`) and
    play its force through the servo loop on a virtual clock, as a replay does.

    Path time 0 is the data set's first frame; past its last frame the flow holds still, or,
    with ``loop``, the frames repeat: over the period the data set states (a periodic flow such
    as vortex shedding), else over their span."""
    from brushes.stylus import StylusSample

    if not (math.isfinite(rate_hz) and 1.0 <= rate_hz <= 1e4):
        raise InputError(f"expected a rate in [1, 10000] Hz, got {rate_hz}", key="--rate")
    times = path.times_s  # type: ignore[attr-defined]
    t0, t1 = float(times[0]), float(times[-1])
    if t1 - t0 > MAX_PATH_S:
        raise InputError(
            f"the path lasts {t1 - t0:.6g} s; at most {MAX_PATH_S:g} s are played (split it)",
            source=getattr(path, "source", None),
            key="t_s",
        )
    count = math.floor((t1 - t0) * rate_hz) + 1
    if count > MAX_EVALUATIONS:
        raise InputError(
            f"the path lasts {t1 - t0:.3g} s: {count} evaluations at {rate_hz:g} Hz; at most "
            f"{MAX_EVALUATIONS} (lower --rate or shorten the path)",
            source=getattr(path, "source", None),
        )
    dim = exploration.flow.dim
    samples = []
    for t in np.linspace(t0, t1, max(count, 2)):
        pos, _ = path.pose_at(float(t))  # type: ignore[attr-defined]
        samples.append(
            StylusSample(float(t), np.array([*pos[:2], pos[2] if dim == 3 else 0.0]), 1.0)
        )
    channel = ForceChannel()
    config = explore_servo_config(force_scale)
    clock = VirtualClock(config.tick_s, start_s=t0)
    device = ReplayDevice(samples, clock.now_s, source=getattr(path, "source", None))
    servo = ServoLoop(device, channel, config)
    servo.open()
    rows = []
    outside = 0
    flow = exploration.flow
    first, span = float(flow.times_s[0]), float(flow.times_s[-1] - flow.times_s[0])
    if isinstance(flow, SampledFlow) and flow.period_s is not None and not loop:
        flow = replace(flow, period_s=None, _frames={})  # hold still after the last frame
        exploration = Exploration(flow, exploration.probe)

    def data_time(t_s: float) -> float:
        offset = t_s - t0
        if loop and flow.period_s is None and span > 0:
            offset %= span
        return first + offset

    for k, sample in enumerate(samples):
        pos, orientation = path.pose_at(sample.t_s)  # type: ignore[attr-defined]
        result = exploration.publish(channel, sample.t_s, pos, orientation, data_time(sample.t_s))
        force, torque = exploration.felt(result)
        outside += result.outside_fraction > 0
        rows.append([sample.t_s, *force, *torque])
        next_t = samples[k + 1].t_s if k + 1 < len(samples) else t1 + 0.1
        target = math.ceil((next_t - t0) / config.tick_s - 1e-9)
        if target > len(servo.log) and not servo.finished:
            servo.run(clock, max_ticks=target - len(servo.log))
        if progress is not None:
            progress(1)  # type: ignore[operator]
    servo.close()
    log = servo.log.arrays()
    trace = np.column_stack([log["t_s"], log["force_n"], log["torque_nm"]])
    return ScriptedRun(trace, np.array(rows), int(outside))
