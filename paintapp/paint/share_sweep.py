"""The share sweep: a step's change of the canvas paint laid along the path the tip swept, its
losses as shares kept (:func:`sweep_shares`; the amount sweep,
:func:`paintapp.paint.columns_kernels.sweep_change`, moves the losses as amounts).

A painting step computes the change with the tip at its end pose only, which alone would print
one tooth per step along a fast stroke. Both sweeps lay it along the path instead: a texel
passed the tip's poses of the step in turn. The amount sweep moves the step's losses back along
the path as amounts, each texel's take capped at its own paint times the largest share lost on
its path; behind a tip whose step is longer than its cells (the probe's, three cells a
sub-step), the texels its path reads were emptied by the step before, their caps bind, and what
they cannot give was taken from the others in proportion, which printed a tooth a step on the
trough's sides. The share sweep follows the texel instead:

Per pigment, with the step's change ``c = new - m`` of the mobile paint ``m`` (paint times
wetness) at the end pose, its gains ``g = max(c, 0)`` and the share ``1 - f`` each texel kept
(``f = max(-c, 0) / m``): a texel ``x`` read the change at ``y_k = x + u_k d`` (``d`` the tip's
travel, ``u_k = (k + 1/2) / K`` for the ``K`` reads, bilinearly), and stood there, relative to
the tip, ``1 - u_k`` of the way through the step. It keeps the share
``exp(s mean_k log(1 - f(y_k)))`` of its paint (a product of the shares kept at its reads: a
texel never loses more than it holds, and one the tip passed twice loses a share twice) and
gains ``mean_k g(y_k)``, each read times the share kept at the reads after it (paint laid early
in the step is partly taken again by the tip's later poses). Every factor is a product along
the path, so the steps that follow one another along a stroke compose into the same product
whatever the step's phase. The exponent ``s``, the same along the path and varying smoothly
across it (:mod:`paintapp.paint.kept_share`), makes the texels lose what the step lost, the loss
keeping its profile across the path; the gains are scaled in the same lanes to what their
texels read without the shares kept, then to the step's gains: both totals kept to float64
round-off.

The moved fields are float32 (the canvas's precision), the passes row by row over the box.
"""

from __future__ import annotations

import numpy as np

from paintapp.paint.columns_kernels import (
    SWEPT_ROUND_OFF,
    _path_samples,
    _sum,
    mobile_shares,
    sweep_reads,
    texel_totals,
)
from paintapp.paint.kept_share import (
    KEEP_FLOOR,
    LANE_SMOOTHING,
    lane_exponents,
    lane_index,
    smooth_lanes,
)
from solver import kernel


@kernel
def _per_read(dx, dy, samples):
    """:func:`paintapp.paint.columns_kernels._path_samples`, each bilinear weight over
    ``samples`` (a read's share of the mean)."""
    offs_i, offs_j, w = _path_samples(dx, dy, samples)
    for k in range(samples):
        for c in range(4):
            w[k, c] /= samples
    return offs_i, offs_j, w


@kernel
def _swept_losses(fields, path, loss_s, log_kept):
    """The losses moved back along the path, in one pass over the rows: ``fields`` = (change,
    log_keep), each (ny, nx) float32 padded with ``pad_y`` rows and ``pad_x`` columns of zeros
    on every side (at least ``|d| + 1``), ``log_keep`` the log of the share each texel kept
    (0 where it lost nothing); ``path`` = (pad_x, pad_y, dx, dy, samples). ``loss_s`` (ny, nx)
    float32 gets the mean of the losses read (the negative changes, as amounts), ``log_kept``
    the mean of the logs read. Returns the sum of ``loss_s`` in float64."""
    change, log_keep = fields
    pad_x, pad_y, dx, dy, samples = path
    ny, nx = loss_s.shape
    lost = 0.0
    offs_i, offs_j, w = _per_read(dx, dy, samples)
    zero = np.float32(0.0)
    for y in range(ny):
        l_out, k_out = loss_s[y], log_kept[y]
        for x in range(nx):
            l_out[x], k_out[x] = zero, zero
        for k in range(samples):
            ya = np.uint64(y + pad_y + offs_j[k])
            yb = ya + np.uint64(1)
            ca, cb, fa, fb = change[ya], change[yb], log_keep[ya], log_keep[yb]
            w00, w10 = np.float32(w[k, 0]), np.float32(w[k, 1])
            w01, w11 = np.float32(w[k, 2]), np.float32(w[k, 3])
            xo = pad_x + offs_i[k]
            for x in range(nx):
                xa = np.uint64(x + xo)
                xb = xa + np.uint64(1)
                l_out[x] += (
                    w00 * max(-ca[xa], zero)
                    + w10 * max(-ca[xb], zero)
                    + w01 * max(-cb[xa], zero)
                    + w11 * max(-cb[xb], zero)
                )
                k_out[x] += w00 * fa[xa] + w10 * fa[xb] + w01 * fb[xa] + w11 * fb[xb]
        lost += _sum(l_out)
    return lost


@kernel
def _swept_gains(fields, path, gain_s, lanes):
    """The gains moved back along the path, each read times the share kept at the reads after
    it, in one pass over the rows: ``fields`` = (change, kept), padded as for
    :func:`_swept_losses`, ``kept`` each texel's share kept at one read (1 where it lost
    nothing). ``gain_s`` (ny, nx) float32 gets the sum over the reads, latest first, of the
    gain read times the product of the shares kept read before it; ``lanes`` = (lane, laid,
    plain): each texel's lane (ny, nx), and per lane the sums, in float64, of ``gain_s`` and of
    the gains read without the shares kept (both overwritten)."""
    change, kept = fields
    pad_x, pad_y, dx, dy, samples = path
    lane, laid, plain = lanes
    ny, nx = gain_s.shape
    for b in range(laid.size):
        laid[b], plain[b] = 0.0, 0.0
    offs_i, offs_j, w = _per_read(dx, dy, samples)
    zero, one = np.float32(0.0), np.float32(1.0)
    share = np.empty(nx, np.float32)  # the share kept at the reads so far
    read = np.empty(nx, np.float32)  # the gains read, without the shares kept
    for y in range(ny):
        g_out = gain_s[y]
        for x in range(nx):
            g_out[x], share[x], read[x] = zero, one, zero
        for k in range(samples):
            ya = np.uint64(y + pad_y + offs_j[k])
            yb = ya + np.uint64(1)
            ca, cb, fa, fb = change[ya], change[yb], kept[ya], kept[yb]
            w00, w10 = np.float32(w[k, 0]), np.float32(w[k, 1])
            w01, w11 = np.float32(w[k, 2]), np.float32(w[k, 3])
            n = np.float32(samples)
            xo = pad_x + offs_i[k]
            for x in range(nx):
                xa = np.uint64(x + xo)
                xb = xa + np.uint64(1)
                g = (
                    w00 * max(ca[xa], zero)
                    + w10 * max(ca[xb], zero)
                    + w01 * max(cb[xa], zero)
                    + w11 * max(cb[xb], zero)
                )
                read[x] += g
                g_out[x] += g * share[x]
                share[x] *= n * (w00 * fa[xa] + w10 * fa[xb] + w01 * fb[xa] + w11 * fb[xb])
        lane_row = lane[y]
        for x in range(nx):
            laid[lane_row[x]] += g_out[x]
            plain[lane_row[x]] += read[x]


@kernel
def _shares_kept(log_keep, lanes, scale, samples):
    """``log_keep`` (padded, as :func:`_swept_losses` takes it) turned in place into the share
    kept at one read, ``exp(s log_keep / samples)`` (1 where nothing was lost), ``s`` the
    texel's lane's exponent: ``lanes`` = (lane, pad_x, pad_y)."""
    lane, pad_x, pad_y = lanes
    rows, cols = log_keep.shape
    for y in range(rows):
        row = log_keep[y]
        for x in range(cols):
            v = row[x]
            if v < 0.0:  # only within the box: the padding is 0
                row[x] = np.float32(np.exp(scale[lane[y - pad_y, x - pad_x]] * v / samples))
            else:
                row[x] = np.float32(1.0)


@kernel
def _fields(paint, box, new_mobile, p, fields):
    """The pigment ``p``'s change and log of the share kept per texel of the box into the padded
    ``fields`` = (change, log_keep), its mobile paint into ``mobile``: ``box`` = (x0, y0, pad_x,
    pad_y, share, mobile). Returns the step's gains and losses, float64."""
    x0, y0, pad_x, pad_y, share, mobile = box
    change, log_keep = fields
    ny, nx = mobile.shape
    gained, lost = 0.0, 0.0
    for y in range(ny):
        row = paint[p, y0 + y, x0 : x0 + nx]
        change_row = change[pad_y + y, pad_x : pad_x + nx]
        keep_row = log_keep[pad_y + y, pad_x : pad_x + nx]
        share_row, mobile_row, new_row = share[y], mobile[y], new_mobile[p, y]
        for x in range(nx):
            m = row[x] * share_row[x]
            mobile_row[x] = m
            c = new_row[x] - m
            change_row[x] = c
            if c > 0.0:
                gained += c
                keep_row[x] = 0.0
            elif c < 0.0:
                lost -= c
                kept = 1.0 + c / m if m > 0.0 else 0.0
                keep_row[x] = np.log(max(kept, KEEP_FLOOR))
            else:
                keep_row[x] = 0.0
    return gained, lost


@kernel
def sweep_shares(paint, wetness, x0, y0, new_mobile, touched, total, dx, dy, spacing, active):
    """Lay a step's change of mobile paint along the path the tip swept, its losses as shares
    kept, in place (the module's docstring gives the rule); the arguments, the result and the
    cases left unswept are :func:`paintapp.paint.columns_kernels.sweep_change`'s: ``paint``
    (P, H, W) and ``wetness`` (H, W) the canvas's float32 arrays, the box's first texel at
    (``x0``, ``y0``), ``new_mobile`` (P, ny, nx) the step's new mobile paint there with the tip
    at its end pose, ``(dx, dy)`` texels the tip's travel during the step, read every
    ``spacing`` texels or closer (as :func:`paintapp.paint.columns_kernels.sweep_reads` counts
    the reads). A pigment whose
    swept amounts miss the step's by more than :data:`SWEPT_ROUND_OFF` of them (the box cut
    short at the canvas's edge), or whose texels on the path hold less than its loss, keeps its
    unswept change. ``touched`` and ``total`` are updated; a pigment ``active`` (P,) does not
    mark is left as it is. Returns whether anything was swept."""
    n_p, ny, nx = new_mobile.shape
    samples, pad_x, pad_y = sweep_reads(dx, dy, spacing)
    if samples == 0:
        return False
    padded = (ny + 2 * pad_y, nx + 2 * pad_x)
    change, log_keep = np.zeros(padded, np.float32), np.zeros(padded, np.float32)
    gain_s = np.empty((ny, nx), np.float32)
    loss_s = np.empty((ny, nx), np.float32)
    log_kept = np.empty((ny, nx), np.float32)
    scratch = (np.empty(ny * nx), np.empty(ny * nx))  # the texels that lose, for the exponent
    lane = np.empty((ny, nx), np.int64)
    count = lane_index(dx, dy, lane)
    lane_scale, laid, plain = np.empty(count), np.empty(count), np.empty(count)
    spread = np.empty(count)  # each lane's gains' scale
    mobile = np.empty((ny, nx))
    share = mobile_shares(wetness, x0, y0, ny, nx)
    box = (x0, y0, pad_x, pad_y, share, mobile)
    path = (pad_x, pad_y, dx, dy, samples)
    done = False
    for p in range(n_p):
        if not active[p]:
            continue
        gained, lost = _fields(paint, box, new_mobile, p, (change, log_keep))
        if gained == 0.0 and lost == 0.0:
            continue
        swept_lost = _swept_losses((change, log_keep), path, loss_s, log_kept)
        if abs(swept_lost - lost) > SWEPT_ROUND_OFF * lost:
            continue  # the box was cut short behind the change (the canvas's edge)
        if lost > 0.0 and not lane_exponents(
            (loss_s, log_kept), mobile, lane, scratch, lost, lane_scale
        ):
            continue  # the texels on the path hold too little: keep the unswept change
        _shares_kept(log_keep, (lane, pad_x, pad_y), lane_scale, samples)
        _swept_gains((change, log_keep), path, gain_s, (lane, laid, plain))
        if abs(_sum(plain) - gained) > SWEPT_ROUND_OFF * gained:
            continue  # the box was cut short behind the change
        _lane_spread(spread, (laid, plain), gained)
        _apply(new_mobile[p], (mobile, log_kept, gain_s, lane), lane_scale, spread, touched)
        done = True
    if done:
        texel_totals(paint, (x0, y0, share), new_mobile, total)
    return done


@kernel
def _lane_spread(spread, sums, gained):
    """The scale of each lane's swept gains into ``spread``: ``sums`` = (laid, plain), per lane
    the swept gains and the gains read without the shares kept; each lane's gains are scaled to
    its plain ones, the scales averaged over :data:`LANE_SMOOTHING` lanes to either side, and
    all of them scaled so that the gains laid are ``gained`` (0 without gains)."""
    laid, plain = sums
    for b in range(spread.size):
        spread[b] = plain[b] / laid[b] if laid[b] > 0.0 else 1.0
    smooth_lanes(spread, plain, LANE_SMOOTHING, 1.0)
    total = 0.0
    for b in range(spread.size):
        total += spread[b] * laid[b]
    for b in range(spread.size):
        spread[b] = spread[b] * gained / total if gained > 0.0 and total > 0.0 else 0.0


@kernel
def _apply(new_mobile, swept, scale, spread, touched):
    """Each texel's new mobile paint into ``new_mobile`` (ny, nx): ``swept`` = (mobile,
    log_kept, gain_s, lane), its paint times its share kept, ``exp(s log_kept)``, plus its
    swept gains times ``g``, where ``s`` and ``g`` are its lane's entries of ``scale`` and
    ``spread``; the texels that change are marked in ``touched``."""
    mobile, log_kept, gain_s, lane = swept
    ny, nx = mobile.shape
    for y in range(ny):
        k_row, m_row, g_row, b_row = log_kept[y], mobile[y], gain_s[y], lane[y]
        t_row, new_row = touched[y], new_mobile[y]
        for x in range(nx):
            m, v, b = m_row[x], k_row[x], b_row[x]
            new = (np.exp(scale[b] * v) * m if v < 0.0 else m) + spread[b] * g_row[x]
            if new != m:
                t_row[x] = True
            new_row[x] = new
