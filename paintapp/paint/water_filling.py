"""The sweep's water-filling (:func:`paintapp.paint.columns_kernels.sweep_change`): the scale
``s`` at which fractions ``f`` of amounts ``m``, each take capped at its whole amount, take a
given loss: ``taken(s) = sum min(s f, 1) m = lost``.

``taken`` is piecewise linear, increasing and concave in ``s``, with a break where ``s f = 1``
for each texel; :func:`water_fill` solves it by Newton's method. :func:`capacity` is the first
pass the sweep makes: what scale 1 takes, the largest fraction, and all that the amounts hold
(when that is less than the loss, no scale takes it).
"""

from __future__ import annotations

import numpy as np

from solver import kernel


@kernel
def _taken_slope(frac, mobile, scale):
    """``(sum min(scale f, 1) m, sum of f m where scale f < 1, largest f where m > 0, sum of m
    where f > 0)`` over the flat arrays ``frac`` and ``mobile``, in four interleaved partial sums
    each: what the fractions take at ``scale``, the slope there, and the most they can take at
    any scale (every texel emptied)."""
    size = frac.size
    t0 = t1 = t2 = t3 = 0.0
    d0 = d1 = d2 = d3 = 0.0
    r0 = r1 = r2 = r3 = 0.0
    top = 0.0
    end = size - size % 4
    for n in range(0, end, 4):
        f0, f1, f2, f3 = frac[n], frac[n + 1], frac[n + 2], frac[n + 3]
        m0, m1, m2, m3 = mobile[n], mobile[n + 1], mobile[n + 2], mobile[n + 3]
        t0 += min(scale * f0, 1.0) * m0
        t1 += min(scale * f1, 1.0) * m1
        t2 += min(scale * f2, 1.0) * m2
        t3 += min(scale * f3, 1.0) * m3
        d0 += f0 * m0 if scale * f0 < 1.0 else 0.0
        d1 += f1 * m1 if scale * f1 < 1.0 else 0.0
        d2 += f2 * m2 if scale * f2 < 1.0 else 0.0
        d3 += f3 * m3 if scale * f3 < 1.0 else 0.0
        r0 += m0 if f0 > 0.0 else 0.0
        r1 += m1 if f1 > 0.0 else 0.0
        r2 += m2 if f2 > 0.0 else 0.0
        r3 += m3 if f3 > 0.0 else 0.0
        top = max(top, max(f0 if m0 > 0.0 else 0.0, f1 if m1 > 0.0 else 0.0))
        top = max(top, max(f2 if m2 > 0.0 else 0.0, f3 if m3 > 0.0 else 0.0))
    for n in range(end, size):
        t0 += min(scale * frac[n], 1.0) * mobile[n]
        d0 += frac[n] * mobile[n] if scale * frac[n] < 1.0 else 0.0
        r0 += mobile[n] if frac[n] > 0.0 else 0.0
        top = max(top, frac[n] if mobile[n] > 0.0 else 0.0)
    taken, slope, room = (t0 + t1) + (t2 + t3), (d0 + d1) + (d2 + d3), (r0 + r1) + (r2 + r3)
    return taken, slope, top, room


@kernel
def capacity(frac, mobile):
    """``(taken, slope, largest f, room)`` at scale 1 (:func:`_taken_slope`): the sweep's
    first pass."""
    return _taken_slope(frac, mobile, 1.0)


@kernel
def _kept_slope(frac, mobile, size, scale):
    """``(sum of f m, new size, sum of the m moved out)`` over the first ``size`` entries of the
    flat arrays ``frac`` and ``mobile``, moving out those that ``scale`` empties
    (``scale f >= 1``): the rest are packed, in order, at the front of both arrays."""
    slope, emptied = 0.0, 0.0
    kept = 0
    for n in range(size):
        f, m = frac[n], mobile[n]
        if scale * f < 1.0:
            slope += f * m
            frac[kept], mobile[kept] = f, m
            kept += 1
        else:
            emptied += m
    return slope, kept, emptied


@kernel
def water_fill(frac_s, mobile, scale, lost):
    """``(scale, taken)``: the scale at which the swept fractions take ``lost`` (to 1e-12 of
    it), from ``scale``, and what they take, ``taken = sum min(scale f, 1) m`` (after 31 passes
    without getting there: what the last pass took, before its step). ``frac_s`` and ``mobile``
    are scratch: their entries are reordered and overwritten.

    ``taken(s) = sum min(s f, 1) m`` is piecewise linear, increasing and concave in ``s``, so
    Newton's method (the slope: the ``f m`` of the texels not yet emptied) reaches the root from
    below monotonically and is exact once the set of emptied texels is right: two to eight passes
    on a painting window's texels (five to eight where most of them are emptied at the root)
    where the fixed-point step ``s *= lost / taken`` took three to 31, its cap, at which it had
    stopped short of the root (and the sweep then kept the step's unswept change). A step that
    would not leave ``s > 0`` (from above the root with most of the paint in emptied texels), or
    no slope, falls back to that fixed-point step. Once a pass has taken less than ``lost``,
    every later scale is larger (a step from below the root stays below it), so a texel that a
    later pass finds emptied stays emptied: that pass moves it out of the arrays and keeps only
    its sum (:func:`_kept_slope`), and the passes grow shorter."""
    frac, held = frac_s.reshape(-1), mobile.reshape(-1)
    size, emptied, below = frac.size, 0.0, False
    taken = 0.0
    for _ in range(31):
        if below:
            slope, size, out = _kept_slope(frac, held, size, scale)
            emptied += out
            taken = scale * slope + emptied
        else:
            taken, slope, _, _ = _taken_slope(frac[:size], held[:size], scale)
            taken += emptied
        if taken <= 0.0 or abs(taken - lost) <= 1e-12 * lost:
            break
        below = taken < lost
        step = scale + (lost - taken) / slope if slope > 0.0 else 0.0
        scale = step if step > 0.0 and np.isfinite(step) else scale * lost / taken
    return scale, taken
