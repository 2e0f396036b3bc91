"""A flow computed elsewhere: pressure and velocity sampled on a regular grid, one frame or a time
series, queried at arbitrary points and times.

Samples sit at the grid's nodes ``origin + index * spacing`` (point data, as CFD tools export on
image data). Between nodes values are multilinear, between frames linear in time; points outside
the grid take the value at the nearest point of its boundary (and are counted, so a caller can
tell). Velocity gradients are central differences at the nodes (one-sided at the grid's edges),
interpolated like the values.

Nodes may be marked as not fluid (inside a body of the data set): their pressure is extended from
the fluid next to them (a few sweeps of neighbour averages), so that a surface lying between
nodes reads the fluid's pressure, not whatever the file holds inside the body; their velocity is
the file's (a no-slip body's own velocity), or zero where the file has none (non-finite).

A flow may come with its velocity gradient already sampled (``gradient_per_s``, e.g. taken on
the unstructured mesh it was resampled from, where the wall is resolved): then that gradient is
used (extended into non-fluid nodes like the pressure) instead of differences of the velocity.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

#: Sweeps of neighbour averaging that extend the fluid's pressure into non-fluid nodes.
EXTENSION_SWEEPS = 4


@dataclass
class SampledFlow:
    """Pressure and velocity on a regular grid.

    Attributes:
        origin_m: position of node 0, shape (dim,), metres.
        spacing_m: node spacing per axis, shape (dim,), metres, > 0.
        times_s: frame times, shape (T,), strictly increasing (one frame: any single time).
        pressure_pa: shape (T, *nodes), Pa.
        velocity_m_s: shape (T, dim, *nodes), m/s.
        density_kg_m3: fluid density.
        viscosity_pa_s: dynamic viscosity.
        fluid: shape nodes, True where the node is in the fluid (None: everywhere).
        period_s: for a periodic series (frames evenly over one period, the last one period
            minus a frame interval after the first): queries wrap around it, and between the last
            frame and the first one period later values are interpolated. None: times outside the
            frames' span are clamped.
        gradient_per_s: the velocity gradient ``G[i, j] = du_i/dx_j`` as sampled, shape
            (T, dim, dim, *nodes), 1/s (None: differences of the velocity).
        cache_frames: how many frames' pressure and gradient :meth:`frame` keeps.
    """

    origin_m: np.ndarray
    spacing_m: np.ndarray
    times_s: np.ndarray
    pressure_pa: np.ndarray
    velocity_m_s: np.ndarray
    density_kg_m3: float
    viscosity_pa_s: float
    fluid: np.ndarray | None = None
    period_s: float | None = None
    gradient_per_s: np.ndarray | None = None
    cache_frames: int = 3
    _frames: dict[int, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict, repr=False)

    def __post_init__(self) -> None:
        self.origin_m = np.asarray(self.origin_m, dtype=np.float64)
        self.spacing_m = np.asarray(self.spacing_m, dtype=np.float64)
        self.times_s = np.atleast_1d(np.asarray(self.times_s, dtype=np.float64))
        dim = self.dim
        if dim not in (2, 3) or self.spacing_m.shape != (dim,):
            raise ValueError("origin and spacing must both have 2 or 3 entries")
        if not (np.all(np.isfinite(self.spacing_m)) and np.all(self.spacing_m > 0)):
            raise ValueError("spacing must be finite and > 0")
        nodes = self.nodes
        if len(nodes) != dim or min(nodes) < 2:
            raise ValueError(f"pressure must have {dim} axes of at least 2 nodes after the frames")
        if self.velocity_m_s.shape != (len(self.times_s), dim, *nodes):
            raise ValueError("velocity must have shape (frames, dim, *nodes)")
        if self.pressure_pa.shape[0] != len(self.times_s):
            raise ValueError("one pressure frame per time")
        if len(self.times_s) > 1 and not np.all(np.diff(self.times_s) > 0):
            raise ValueError("frame times must increase")
        if self.fluid is not None and self.fluid.shape != nodes:
            raise ValueError("the fluid mask must have the nodes' shape")
        if self.period_s is not None and not (
            np.isfinite(self.period_s) and self.period_s > self.times_s[-1] - self.times_s[0]
        ):
            raise ValueError("the period must be finite and longer than the frames' span")
        if self.gradient_per_s is not None and self.gradient_per_s.shape != (
            len(self.times_s),
            dim,
            dim,
            *nodes,
        ):
            raise ValueError("the gradient must have shape (frames, dim, dim, *nodes)")

    @property
    def dim(self) -> int:
        return len(self.origin_m)

    @property
    def nodes(self) -> tuple[int, ...]:
        return tuple(self.pressure_pa.shape[1:])

    @property
    def extent_m(self) -> tuple[np.ndarray, np.ndarray]:
        """Lowest and highest node positions, (dim,) each."""
        return self.origin_m, self.origin_m + self.spacing_m * (np.array(self.nodes) - 1)

    def frame(self, index: int) -> tuple[np.ndarray, np.ndarray]:
        """Pressure (extended into non-fluid nodes) and velocity gradient ``G[i, j] = du_i/dx_j``
        (shape (dim, dim, *nodes)) of frame ``index``; the last few frames are kept."""
        if index not in self._frames:
            if len(self._frames) >= max(self.cache_frames, 1):
                self._frames.pop(next(iter(self._frames)))
            p = self.pressure_pa[index].astype(np.float64)
            u = self.velocity_m_s[index].astype(np.float64)
            if self.gradient_per_s is not None:
                grad = self.gradient_per_s[index].astype(np.float64)
                if self.fluid is not None:
                    p = extend_into(p, self.fluid)
                    for i in range(self.dim):
                        for j in range(self.dim):
                            grad[i, j] = extend_into(grad[i, j], self.fluid)
            elif self.fluid is None:
                grad = np.stack(
                    [
                        np.stack(np.gradient(u[i], *self.spacing_m, edge_order=1))
                        for i in range(self.dim)
                    ]
                )
            else:
                p = extend_into(p, self.fluid)
                u = np.nan_to_num(np.where(self.fluid[None] | np.isfinite(u), u, 0.0))
                grad = wall_gradient(u, self.fluid, self.spacing_m)
            self._frames[index] = (p, grad)
        return self._frames[index]

    def sample(self, t_s: float, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
        """Pressure (n,) and velocity gradient (n, dim, dim) at ``points`` (n, dim) and time
        ``t_s`` (clamped to the frames' span), and how many points lay outside the grid."""
        points = np.asarray(points, dtype=np.float64)
        lo, hi = self.extent_m
        outside = int(np.count_nonzero(np.any((points < lo) | (points > hi), axis=1)))
        index, corner_weights = _multilinear(points, self.origin_m, self.spacing_m, self.nodes)
        i0, i1, a = frame_pair(self.times_s, t_s, self.period_s)
        p0, g0 = self.frame(i0)
        p, g = _gather(p0, g0, index, corner_weights)
        if a > 0.0:
            p1, g1 = self.frame(i1)
            q, h = _gather(p1, g1, index, corner_weights)
            p, g = (1.0 - a) * p + a * q, (1.0 - a) * g + a * h
        return p, g, outside


def wall_gradient(u: np.ndarray, fluid: np.ndarray, spacing: np.ndarray) -> np.ndarray:
    """Velocity gradient ``G[i, j]`` (dim, dim, *nodes) from fluid nodes only: central
    differences between fluid nodes; next to a body, the difference to the body's node taken
    over half a spacing (the wall is assumed halfway between a fluid and a body node, as a mask
    of nodes implies); then extended into the body's nodes from the fluid next to them."""
    dim = u.shape[0]
    grad = np.empty((dim, dim, *fluid.shape))
    for j in range(dim):
        h = float(spacing[j])

        def shifted(a: np.ndarray, step: int, axis: int = j) -> np.ndarray:
            n = a.shape[axis]
            return np.take(a, np.clip(np.arange(n) + step, 0, n - 1), axis=axis)

        lo_fluid, hi_fluid = shifted(fluid, -1), shifted(fluid, 1)
        at_lo_edge = np.zeros(fluid.shape, dtype=bool)
        at_hi_edge = np.zeros(fluid.shape, dtype=bool)
        np.moveaxis(at_lo_edge, j, 0)[0] = True
        np.moveaxis(at_hi_edge, j, 0)[-1] = True
        for i in range(dim):
            q = u[i]
            lo, hi = shifted(q, -1, j), shifted(q, 1, j)
            central = (hi - lo) / (2 * h)
            one_hi = (hi - q) / h  # forward, within the fluid
            one_lo = (q - lo) / h
            wall_lo = (q - lo) / (0.5 * h)  # toward a body node below
            wall_hi = (hi - q) / (0.5 * h)
            g = central
            g = np.where(at_lo_edge, one_hi, g)
            g = np.where(at_hi_edge, one_lo, g)
            g = np.where(~lo_fluid & ~at_lo_edge & hi_fluid, wall_lo, g)
            g = np.where(~hi_fluid & ~at_hi_edge & lo_fluid, wall_hi, g)
            g = np.where(
                ~lo_fluid & ~hi_fluid & ~at_lo_edge & ~at_hi_edge, 0.5 * (wall_lo + wall_hi), g
            )
            grad[i, j] = extend_into(g, fluid)
    return grad


def extend_into(
    values: np.ndarray, fluid: np.ndarray, sweeps: int = EXTENSION_SWEEPS
) -> np.ndarray:
    """``values`` with non-fluid nodes set from their known neighbours, sweep by sweep (nodes
    still unknown after ``sweeps`` take the fluid's mean)."""
    out = np.where(fluid, values, 0.0).astype(np.float64)
    known = fluid.copy()
    for _ in range(sweeps):
        total = np.zeros_like(out)
        count = np.zeros(out.shape)
        for axis in range(out.ndim):
            for shift in (-1, 1):
                rolled_v = np.roll(np.where(known, out, 0.0), shift, axis)
                rolled_k = np.roll(known, shift, axis)
                edge: list[slice | int] = [slice(None)] * out.ndim
                edge[axis] = 0 if shift == 1 else -1
                rolled_k[tuple(edge)] = False  # no wrap-around
                total += np.where(rolled_k, rolled_v, 0.0)
                count += rolled_k
        fill = ~known & (count > 0)
        if not fill.any():
            break
        out[fill] = total[fill] / count[fill]
        known = known | fill
    if not known.all():
        out[~known] = float(values[fluid].mean()) if fluid.any() else 0.0
    return out


def frame_pair(
    times: np.ndarray, t_s: float, period_s: float | None = None
) -> tuple[int, int, float]:
    """The frames around ``t_s`` and the weight of the later one: clamped to the frames' span,
    or wrapped around ``period_s`` (between the last frame and the first one period on)."""
    if period_s is not None and len(times) > 1:
        first, last = float(times[0]), float(times[-1])
        t_s = first + (t_s - first) % period_s
        if t_s > last:
            return len(times) - 1, 0, float((t_s - last) / (first + period_s - last))
    if len(times) == 1 or t_s <= times[0]:
        return 0, 0, 0.0
    if t_s >= times[-1]:
        return len(times) - 1, len(times) - 1, 0.0
    i = int(np.searchsorted(times, t_s, side="right")) - 1
    return i, i + 1, float((t_s - times[i]) / (times[i + 1] - times[i]))


def _multilinear(
    points: np.ndarray, origin: np.ndarray, spacing: np.ndarray, nodes: tuple[int, ...]
) -> tuple[list[tuple[np.ndarray, ...]], list[np.ndarray]]:
    """Corner node indices and weights of every point (clamped into the grid)."""
    s = (points - origin) / spacing
    n = np.array(nodes)
    s = np.clip(s, 0.0, n - 1)
    base = np.minimum(np.floor(s).astype(np.int64), n - 2)
    frac = s - base
    dim = len(nodes)
    index, weights = [], []
    for corner in range(2**dim):
        bits = [(corner >> a) & 1 for a in range(dim)]
        index.append(tuple(base[:, a] + bits[a] for a in range(dim)))
        w = np.ones(len(points))
        for a in range(dim):
            w = w * (frac[:, a] if bits[a] else 1.0 - frac[:, a])
        weights.append(w)
    return index, weights


def _gather(
    p: np.ndarray, grad: np.ndarray, index: list[tuple[np.ndarray, ...]], weights: list[np.ndarray]
) -> tuple[np.ndarray, np.ndarray]:
    out_p = np.zeros(len(weights[0]))
    out_g = np.zeros((*grad.shape[:2], len(weights[0])))
    for idx, w in zip(index, weights, strict=True):
        out_p += w * p[idx]
        full: tuple[slice | np.ndarray, ...] = (slice(None), slice(None), *idx)
        out_g += w * grad[full]
    return out_p, np.moveaxis(out_g, -1, 0)
