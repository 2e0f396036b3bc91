"""A step's change laid along the tip's path, its losses as shares kept (share_sweep)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq

from paintapp.paint.columns_kernels import sweep_change
from paintapp.paint.kept_share import KEEP_FLOOR, keep_exponent
from paintapp.paint.share_sweep import sweep_shares

#: Relative agreement of the kernel's float32 fields with the float64 reference, per texel.
F32 = 2e-5


def bilinear(field: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """``field`` (ny, nx) read at texel offsets (x, y) (whole numbers at texels), 0 outside."""
    ny, nx = field.shape
    i0, j0 = np.floor(x).astype(int), np.floor(y).astype(int)
    fx, fy = x - i0, y - j0
    out = np.zeros(np.broadcast(x, y).shape)
    for dj, wy in ((0, 1 - fy), (1, fy)):
        for di, wx in ((0, 1 - fx), (1, fx)):
            j, i = j0 + dj, i0 + di
            ok = (0 <= j) & (j < ny) & (0 <= i) & (i < nx)
            out[ok] += (wy * wx)[ok] * field[j[ok], i[ok]]
    return out


def reference(mobile: np.ndarray, new: np.ndarray, travel: tuple[float, float], samples: int):
    """The share sweep's rule in float64, one pigment ((ny, nx) arrays), as its module says."""
    c = new - mobile
    gain = np.maximum(c, 0.0)
    safe = np.where(mobile > 0.0, mobile, 1.0)
    log_keep = np.where(c < 0.0, np.log(np.maximum(1.0 + c / safe, KEEP_FLOOR)), 0.0)
    ys, xs = np.mgrid[0 : c.shape[0], 0 : c.shape[1]].astype(float)
    reads = [
        (xs + (k + 0.5) / samples * travel[0], ys + (k + 0.5) / samples * travel[1])
        for k in range(samples)
    ]
    mean_log = sum(bilinear(log_keep, *r) for r in reads) / samples
    losing = (mean_log < 0.0) & (mobile > 0.0)
    lost = np.maximum(-c, 0.0).sum()

    def taken(s: float) -> float:
        return float((mobile[losing] * (1.0 - np.exp(s * mean_log[losing]))).sum() - lost)

    s = brentq(taken, 1e-6, 1e3, xtol=1e-14) if lost > 0.0 else 0.0
    kept_at_read = np.exp(s * log_keep / samples)
    laid, share = np.zeros_like(c), np.ones_like(c)
    for r in reads:  # the latest read first
        laid += bilinear(gain, *r) / samples * share
        share *= bilinear(kept_at_read - 1.0, *r) + 1.0  # the shares kept read 1 off the box
    spread = gain.sum() / laid.sum() if gain.sum() > 0.0 else 0.0
    return mobile * np.exp(s * mean_log) + spread * laid, s


def one_pigment_step(seed: int):
    """A (1, 30, 50) wet canvas of uneven paint and a tip's step in it: a patch that lost a
    share of its paint (all of it in a core), a heap laid ahead, a film laid behind."""
    rng = np.random.default_rng(seed)
    paint = rng.uniform(2e-6, 2e-5, (1, 30, 50)).astype(np.float32)
    wet = np.ones((30, 50), np.float32)
    mobile = paint.astype(np.float64)
    new = mobile.copy()
    new[0, 10:20, 22:30] *= 0.4
    new[0, 13:17, 26:30] = 0.0
    new[0, 10:20, 30:33] += 3e-5
    new[0, 10:20, 18:22] += 2e-6
    return paint, wet, mobile, new


def test_the_sweep_follows_its_rule():
    # Rows alike and a path along them (four reads over 3.6 texels): every lane (a row) then has
    # the same exponent and gain scale, and the rule is the whole box's; the kernel's fields
    # are float32.
    rng = np.random.default_rng(1)
    paint = np.repeat(rng.uniform(2e-6, 2e-5, (1, 1, 50)), 24, axis=1).astype(np.float32)
    wet = np.ones((24, 50), np.float32)
    mobile = paint.astype(np.float64)
    new = mobile.copy()
    new[0, :, 22:30] *= 0.4
    new[0, :, 26:28] = 0.0
    new[0, :, 30:33] += 3e-5
    new[0, :, 18:22] += 2e-6
    out = new.copy()
    touched, total = np.zeros((24, 50), bool), np.zeros((24, 50))
    assert sweep_shares(paint, wet, 0, 0, out, touched, total, 3.6, 0.0, 1.0, np.ones(1, bool))
    expected, s = reference(mobile[0], new[0], (3.6, 0.0), 4)
    assert 0.2 < s < 5.0
    np.testing.assert_allclose(out[0], expected, rtol=F32, atol=F32 * 2e-5)
    np.testing.assert_allclose(out.sum(), new.sum(), rtol=1e-12)
    np.testing.assert_allclose(total, out[0], rtol=1e-12)  # all wet: no dry part
    assert touched[out[0] != mobile[0]].all()


def test_the_loss_keeps_its_profile_across_the_path():
    # Two wide bands beside each other lose 80 % and 10 % of the paint of a patch and heap it
    # ahead, each row what it lost: each row's paint is kept but where the lanes' exponents
    # blend at the seam (twenty lanes to either side), however much paint each band holds
    paint = np.full((1, 160, 60), 1e-5, np.float32)
    paint[0, 80:] = 3e-5
    wet = np.ones((160, 60), np.float32)
    mobile = paint.astype(np.float64)
    new = mobile.copy()
    new[0, :80, 30:38] *= 0.2
    new[0, 80:, 30:38] *= 0.9
    new[0, :, 38:42] += (mobile - new)[0, :, 30:38].sum(axis=1, keepdims=True) / 4
    out = new.copy()
    assert sweep_shares(paint, wet, 0, 0, out, np.zeros((160, 60), bool), np.zeros((160, 60)),
                        6.0, 0.0, 1.0, np.ones(1, bool))  # fmt: skip
    step = np.maximum(mobile - new, 0.0)[0].sum(axis=1)  # what each row lost
    moved = out[0].sum(axis=1) - new[0].sum(axis=1)  # what the sweep moved across the rows
    far = np.r_[0:50, 110:160]  # rows more than 30 from the seam
    assert np.all(np.abs(moved[far]) < 0.02 * step[far])
    assert np.abs(moved).max() > 0.05 * step.min()  # at the seam the lanes blend
    np.testing.assert_allclose(out.sum(), new.sum(), rtol=1e-12)


@settings(max_examples=25, deadline=None)
@given(
    seed=st.integers(0, 10_000),
    dx=st.floats(-9.0, 9.0),
    dy=st.floats(-9.0, 9.0),
    wet_share=st.floats(0.2, 1.0),
)
def test_each_pigment_keeps_its_paint_and_no_texel_goes_below_its_dry_part(seed, dx, dy, wet_share):
    rng = np.random.default_rng(seed)
    paint = rng.uniform(0.0, 2e-5, (3, 30, 50)).astype(np.float32)
    paint[:, rng.random((30, 50)) < 0.2] = 0.0  # bare texels among them
    wet = np.where(rng.random((30, 50)) < 0.5, 1.0, wet_share).astype(np.float32)
    mobile = paint * wet
    new = mobile.astype(np.float64)
    new[:, 10:20, 20:30] *= rng.uniform(0.0, 1.0, (3, 10, 10))
    new[:, 8:22, 30:34] += rng.uniform(0.0, 2e-5, (3, 14, 4))
    out = new.copy()
    touched, total = np.zeros((30, 50), bool), np.zeros((30, 50))
    sweep_shares(paint, wet, 0, 0, out, touched, total, dx, dy, 1.0, np.ones(3, bool))
    np.testing.assert_allclose(out.sum(axis=(1, 2)), new.sum(axis=(1, 2)), rtol=1e-9)
    assert out.min() >= 0.0


def test_a_pigment_that_does_not_change_or_is_not_active_is_left_as_it_is():
    paint, wet, mobile, new = one_pigment_step(2)
    paint = np.concatenate([paint, paint])
    new = np.concatenate([new, mobile])  # pigment 1 unchanged
    out = new.copy()
    touched, total = np.zeros((30, 50), bool), np.zeros((30, 50))
    active = np.array([True, False])
    assert sweep_shares(paint, wet, 0, 0, out, touched, total, 5.0, 0.0, 1.0, active)
    np.testing.assert_array_equal(out[1], new[1])
    assert not np.array_equal(out[0], new[0])


@pytest.mark.parametrize("travel", [(0.3, 0.2), (-40.0, 0.0)])
def test_no_travel_or_a_box_cut_short_leaves_the_change_unswept(travel):
    paint, wet, _, new = one_pigment_step(3)
    out = new.copy()
    sweep_shares(paint, wet, 0, 0, out, np.zeros((30, 50), bool), np.zeros((30, 50)), *travel,
                 1.0, np.ones(1, bool))  # fmt: skip
    np.testing.assert_array_equal(out, new)


def test_a_loss_the_path_cannot_hold_keeps_its_unswept_change():
    # all of one texel's paint taken among texels a ten-thousandth as thick: read from 2.5 and
    # 7.5 texels back, it is laid on texels that hold less than the loss (the texel itself
    # reads it with no weight)
    paint = np.full((1, 20, 40), 1e-9, np.float32)
    paint[0, 10, 20] = 1e-5
    wet = np.ones((20, 40), np.float32)
    new = paint.astype(np.float64)
    new[0, 10, 20] = 0.0
    out = new.copy()
    assert not sweep_shares(paint, wet, 0, 0, out, np.zeros((20, 40), bool), np.zeros((20, 40)),
                            10.0, 0.0, 5.0, np.ones(1, bool))  # fmt: skip
    np.testing.assert_array_equal(out, new)


def test_the_exponent_takes_the_loss_and_says_when_it_cannot():
    log_keep = np.log(np.array([0.9, 0.5, 1e-6, 0.99]))
    held = np.array([1.0, 2.0, 0.5, 3.0])
    for lost in (0.01, 0.8, 3.0):
        s = keep_exponent(log_keep, held, lost)
        assert (held * (1.0 - np.exp(s * log_keep))).sum() == pytest.approx(lost, rel=1e-12)
    assert keep_exponent(log_keep, held, 0.0) == 0.0
    assert keep_exponent(log_keep, held, held.sum()) == -1.0  # only an infinite one would


def drag(sweep, steps: int = 20) -> np.ndarray:
    """A tip that takes half the wet paint under its 8-texel footprint each step (its ends
    weighed by the share of a texel they cover) and heaps it on a ridge beside, moved 5.3
    texels a step along x through an even layer; the canvas's paint after ``steps``."""
    paint = np.full((1, 40, 160), 1e-5, np.float32)
    wet = np.ones((40, 160), np.float32)
    xs, ys = np.arange(160) + 0.5, np.arange(40) + 0.5
    under, beside = (ys > 10) & (ys <= 20), (ys > 20) & (ys <= 23)
    for n in range(steps):
        tip = 20.0 + (n + 1) * 5.3
        cover = np.clip(np.minimum(xs + 0.5, tip) - np.maximum(xs - 0.5, tip - 8.0), 0.0, 1.0)
        new = paint.astype(np.float64)
        taken = 0.5 * new[0] * cover[None, :] * under[:, None]
        ridge = cover[None, :] * beside[:, None]
        new[0] += taken.sum() * ridge / ridge.sum() - taken
        sweep(paint, wet, 0, 0, new, np.zeros((40, 160), bool), np.zeros((40, 160)), 5.3, 0.0,
              1.0, np.ones(1, bool))  # fmt: skip
        paint[:] = new.astype(np.float32)
    return paint[0]


def test_a_steady_drag_leaves_an_even_trail_where_the_amount_sweep_left_teeth():
    # The trough behind the tip, along the path: each step's shares compose into the same
    # product whatever the step's phase, so it is even but for the ripple of the reads (every
    # 0.88 texel, bilinear); the amount sweep's caps bind behind the footprint (its rear was
    # emptied a step before) and print a tooth a step.
    shares = drag(sweep_shares)[12:19, 40:100].mean(axis=0)
    amounts = drag(sweep_change)[12:19, 40:100].mean(axis=0)
    assert np.ptp(shares) < 0.08 * shares.mean()
    assert np.ptp(amounts) > 0.25 * amounts.mean()
    # both take the step's loss: the trough as deep (each step takes half of what is under
    # the footprint as the sweeps left it)
    assert abs(shares.mean() - amounts.mean()) < 0.05 * amounts.mean()
