"""The exponents that make the share sweep's kept shares take a step's loss, lane by lane
(:func:`paintapp.paint.share_sweep.sweep_shares`).

A texel that the swept path says keeps the share ``K`` of its paint (``L = log K``, the mean of
the logs read along its path) keeps ``K**s``. The exponent ``s`` is the same all along the path
(every texel's share is then still a product along its path, and the steps of a stroke compose
whatever their phase) and makes the texels lose what the step lost. Across the path it may
vary: the box is cut into *lanes*, strips :data:`LANE_TEXELS` wide along the path's direction
(a texel's reads lie along its lane); each lane's exponent is the one at which its texels take
its swept loss (the mean of the losses its texels read, which keeps the loss's profile across
the path; a lane whose texels hold less is joined with its neighbours until they hold enough),
averaged over the :data:`LANE_SMOOTHING` lanes to either side, and then all of them are scaled
by one factor that takes the step's loss exactly (:func:`lane_exponents`).

``taken(s) = sum m (1 - exp(s L))`` is increasing and concave in ``s``: Newton's method from
``s = 1`` reaches the root (a step from above lands below it, and from below it climbs
monotonically) (:func:`keep_exponent`).
"""

from __future__ import annotations

import numpy as np

from solver import kernel

#: Least share of its paint a texel keeps at one read (an emptied texel: the log of 0 is not
#: finite); ``exp(s log 1e-9)`` is nothing at any exponent a step needs.
KEEP_FLOOR = 1e-9

#: How closely the texels' take must meet the step's loss, relative.
TOLERANCE = 1e-12

#: Newton passes before :func:`keep_exponent` gives up.
MAX_PASSES = 60

#: Width of a lane across the path, texels: a texel's reads are bilinear, so they stay within
#: its lane and the next.
LANE_TEXELS = 1.0

#: Lanes to either side over which a lane's exponent and its gains' scale are averaged
#: (triangular weights times each lane's loss or gain). A lane's own exponent follows its few
#: texels, whose reads straddle it and its neighbours where the path runs across the texels, and
#: jumps from step to step (combing a brush's sides again); one exponent for the whole box moves
#: the loss across the path, from the sides of a narrow brush's trough into it. Twenty lanes lie
#: between the two (docs/performance.md, the share sweep).
LANE_SMOOTHING = 20


@kernel
def _taken(log_keep, held, scale):
    """``(sum m (1 - exp(s L)), its slope in s)`` over the flat arrays ``log_keep`` (``L``) and
    ``held`` (``m``) at ``scale`` (``s``)."""
    taken, slope = 0.0, 0.0
    for n in range(log_keep.size):
        e = np.exp(scale * log_keep[n])
        taken += held[n] * (1.0 - e)
        slope -= held[n] * log_keep[n] * e
    return taken, slope


@kernel
def keep_exponent(log_keep, held, lost):
    """The exponent ``s`` at which the texels of the flat arrays ``log_keep`` (``L < 0``) and
    ``held`` (``m > 0``) take ``lost`` (``sum m (1 - exp(s L)) = lost`` to :data:`TOLERANCE` of
    it), or -1 if they hold less than ``lost`` or the passes end short of it."""
    if lost <= 0.0:
        return 0.0
    room = 0.0
    for n in range(held.size):
        room += held[n]
    if room < lost * (1.0 + 1e-9):  # only an infinite exponent would take it all
        return -1.0
    scale = 1.0
    for _ in range(MAX_PASSES):
        taken, slope = _taken(log_keep, held, scale)
        if abs(taken - lost) <= TOLERANCE * lost:
            return scale
        step = scale + (lost - taken) / slope if slope > 0.0 else 2.0 * scale
        scale = step if step > 0.0 and np.isfinite(step) else 0.5 * scale
    return -1.0


@kernel
def lane_index(dx, dy, lane):
    """Each texel's lane into ``lane`` (ny, nx) int64 for a path along (``dx``, ``dy``) (not
    both 0): strips :data:`LANE_TEXELS` wide along that direction, numbered from 0 across it.
    Returns the number of lanes."""
    ny, nx = lane.shape
    norm = np.hypot(dx, dy)
    ux, uy = dx / norm, dy / norm
    low = min(0.0, (nx - 1) * uy) - max(0.0, (ny - 1) * ux)
    count = 0
    for y in range(ny):
        for x in range(nx):
            b = int((x * uy - y * ux - low) / LANE_TEXELS)
            lane[y, x] = b
            count = max(count, b + 1)
    return count


@kernel
def smooth_lanes(values, weight, half, default):
    """``values`` averaged in place over the lanes within ``half`` of each, with triangular
    weights times ``weight`` (``default`` where none weighs)."""
    n = values.size
    out = np.empty(n)
    for b in range(n):
        num, den = 0.0, 0.0
        for j in range(max(0, b - half), min(n, b + half + 1)):
            w = (half + 1 - abs(j - b)) * weight[j]
            num += w * values[j]
            den += w
        out[b] = num / den if den > 0.0 else default
    for b in range(n):  # not a slice copy, which compiles a shape check
        values[b] = out[b]


@kernel
def lane_exponents(swept, mobile, lane, scratch, lost, scale):
    """The exponent per lane (into ``scale``) at which the texels take the step's loss
    ``lost``: ``swept`` = (loss, log_kept), each (ny, nx); each lane's exponent is the one at
    which its texels take its swept loss (lanes joined until they hold it), averaged over
    neighbouring lanes, then all scaled by one factor that takes ``lost`` exactly. Returns
    False if the texels hold too little."""
    loss_s, log_kept = swept
    log_keep, held = scratch
    ny, nx = loss_s.shape
    count = scale.size
    want, room = np.zeros(count), np.zeros(count)
    starts = np.zeros(count + 1, np.int64)
    for y in range(ny):
        for x in range(nx):
            b = lane[y, x]
            want[b] += loss_s[y, x]
            if log_kept[y, x] < 0.0 and mobile[y, x] > 0.0:
                starts[b + 1] += 1
                room[b] += mobile[y, x]
    total = 0.0
    for b in range(count):
        total += want[b]
    if total <= 0.0:
        return False
    cursor = np.empty(count, np.int64)
    for b in range(count):
        starts[b + 1] += starts[b]
        cursor[b] = starts[b]
    for y in range(ny):
        for x in range(nx):
            if log_kept[y, x] < 0.0 and mobile[y, x] > 0.0:
                b = lane[y, x]
                n = cursor[b]
                log_keep[n], held[n] = log_kept[y, x], mobile[y, x]
                cursor[b] = n + 1
    for b in range(count):
        want[b] *= lost / total
    if _fill_lanes((log_keep, held), starts, want, room, scale):
        smooth_lanes(scale, want, LANE_SMOOTHING, 1.0)
    else:
        for b in range(count):
            scale[b] = 1.0
    for b in range(count):
        for n in range(starts[b], starts[b + 1]):
            log_keep[n] *= scale[b]
    size = starts[count]
    factor = keep_exponent(log_keep[:size], held[:size], lost)
    if factor < 0.0:
        return False
    for b in range(count):
        scale[b] *= factor
    return True


@kernel
def _fill_lanes(sorted_texels, starts, want, room, scale):
    """Per lane, the exponent (into ``scale``) at which its texels take its loss ``want``
    (the texels sorted by lane, lane ``b``'s at ``starts[b]:starts[b + 1]``; ``room`` each
    lane's paint); a group of lanes closes once its texels hold its loss and shares one
    exponent; lanes left over join the groups before them. False if all cannot."""
    log_keep, held = sorted_texels
    n = want.size
    group = np.empty(n + 1, np.int64)
    groups = 0
    first, need, have = 0, 0.0, 0.0
    for b in range(n):
        need += want[b]
        have += room[b]
        if have >= need * (1.0 + 1e-9):
            a, e = starts[first], starts[b + 1]
            s = keep_exponent(log_keep[a:e], held[a:e], need)
            if s >= 0.0:
                for c in range(first, b + 1):
                    scale[c] = s
                group[groups] = first
                groups += 1
                first, need, have = b + 1, 0.0, 0.0
    while first < n:
        if groups == 0:
            return False
        groups -= 1
        first = group[groups]
        need = have = 0.0
        for b in range(first, n):
            need += want[b]
            have += room[b]
        if have >= need * (1.0 + 1e-9):
            a, e = starts[first], starts[n]
            s = keep_exponent(log_keep[a:e], held[a:e], need)
            if s >= 0.0:
                for c in range(first, n):
                    scale[c] = s
                first = n
    return True
