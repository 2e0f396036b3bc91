"""A grid's fields moved with the grid: by whole cells, or by fractions of a cell.

A grid that follows a probe moves its origin by ``off`` cells per axis; each field sampled on it
then takes ``new[i] = old[i + off]``. By whole cells the samples are copied (:func:`shifted`);
by fractions each axis in turn is interpolated linearly between the two samples the new one
lies between (:func:`shifted_by`). Samples that come from outside the grid are zero.
"""

from __future__ import annotations

import math

import numpy as np

from solver.compiled.jit import kernel


def shifted(q: np.ndarray, off: list[int]) -> np.ndarray:
    """``q`` moved so that new[i] = old[i + off]; entries from outside are zero."""
    out = np.zeros_like(q)
    src, dst = [], []
    for a in range(3):
        n, o = q.shape[a], off[a]
        if abs(o) >= n:
            return out
        src.append(slice(max(o, 0), n + min(o, 0)))
        dst.append(slice(max(-o, 0), n - max(o, 0)))
    out[tuple(dst)] = q[tuple(src)]
    return out


def shifted_by_axes(q: np.ndarray, off: list[float]) -> np.ndarray:
    """:func:`shifted_by` one axis at a time with numpy, a field for each pass: the reference
    the kernel is tested against."""
    out = q
    for a in range(3):
        base = math.floor(off[a])
        frac = off[a] - base
        if base == 0 and frac == 0.0:
            continue
        step = [0, 0, 0]
        step[a] = base
        lo = shifted(out, step)
        if frac > 0.0:
            step[a] = base + 1
            lo = (1.0 - frac) * lo + frac * shifted(out, step)
        out = lo
    return np.ascontiguousarray(out)


@kernel
def _pass(q, base, frac, out):
    """``out`` = ``q`` (n, m) moved along its first axis by ``base + frac`` rows (the rows from
    outside zero), each row blended in :func:`shifted_by_axes`' arithmetic: a blend with a row
    from outside reads 0 there, as numpy's does from its zero-filled copy."""
    n, m = q.shape
    for i in range(n):
        s = i + base
        o = out[i]
        lo_in, hi_in = 0 <= s < n, 0 <= s + 1 < n
        if frac == 0.0:
            if lo_in:
                row = q[s]
                for c in range(m):  # element by element: a slice copy compiles a shape check
                    o[c] = row[c]
            else:
                o[:] = 0.0
            continue
        keep = 1.0 - frac
        if lo_in and hi_in:
            lo, hi = q[s], q[s + 1]
            for c in range(m):
                o[c] = keep * lo[c] + frac * hi[c]
        elif lo_in:
            lo = q[s]
            for c in range(m):
                o[c] = keep * lo[c] + frac * 0.0
        elif hi_in:
            hi = q[s + 1]
            for c in range(m):
                o[c] = keep * 0.0 + frac * hi[c]
        else:
            o[:] = 0.0


@kernel
def _pass_axis(q, axis, base, frac, out):
    """:func:`_pass` along ``axis`` of the 3D ``q``: over its planes (x), over the (y, z) plane
    of each x (y), over each row of z values seen as rows of one value (z)."""
    nx, ny, nz = q.shape
    if axis == 0:
        _pass(q.reshape(nx, ny * nz), base, frac, out.reshape(nx, ny * nz))
    elif axis == 1:
        for i in range(nx):
            _pass(q[i], base, frac, out[i])
    else:
        for i in range(nx):
            for j in range(ny):
                _pass(q[i, j].reshape(nz, 1), base, frac, out[i, j].reshape(nz, 1))


def shifted_by(q: np.ndarray, off: list[float]) -> np.ndarray:
    """``q`` moved by fractions of a cell: new[i] = old at i + off, linearly interpolated along
    each axis in turn; entries from outside are zero. A compiled pass an axis, with the values
    of :func:`shifted_by_axes`, bit for bit."""
    bases = [math.floor(o) for o in off]
    fracs = [o - b for o, b in zip(off, bases, strict=True)]
    out = np.array(q, dtype=np.float64, order="C")  # a copy of its own, as numpy's passes give
    for a in range(3):
        if bases[a] == 0 and fracs[a] == 0.0:
            continue
        moved = np.empty_like(out)
        _pass_axis(out, a, bases[a], fracs[a], moved)
        out = moved
    return out
