"""A step's change laid along the path the tip swept (columns_kernels.sweep_change)."""

from __future__ import annotations

import numpy as np
import pytest

from common.errors import InputError
from paintapp.paint.columns_kernels import sweep_change
from paintapp.paint.paint_scene import parse_paint_scene

#: Relative round-off of a value of the sweep's float32 fields (float32's epsilon, 1.2e-7, and
#: a little): per texel the swept values agree with float64 arithmetic to this.
F32 = 2e-7


def every(paint: np.ndarray) -> np.ndarray:
    """Every pigment of ``paint`` (P, H, W) marked as changing."""
    return np.ones(len(paint), np.bool_)


def canvas_and_change(rng: np.random.Generator, pigments: int = 2):
    """A (P, 40, 60) wet canvas, its box at (5, 3) of (30, 50) texels, and new mobile paint
    there: a gain ahead of a patch that lost paint, as a tip leaves them."""
    paint = rng.uniform(1e-6, 1e-5, (pigments, 40, 60)).astype(np.float32)
    wet = np.ones((40, 60), np.float32)
    mobile = paint[:, 3:33, 5:55].astype(np.float64)
    new = mobile.copy()
    new[:, 10:20, 30:36] *= 0.2  # taken away
    new[:, 10:20, 36:40] += 2e-5  # heaped ahead
    return paint, wet, mobile, new


def test_gains_are_laid_as_their_mean_along_the_path_and_totals_kept():
    rng = np.random.default_rng(1)
    paint, wet, mobile, new = canvas_and_change(rng)
    out = new.copy()
    touched = np.zeros((30, 50), bool)
    total = np.zeros((30, 50))
    assert sweep_change(paint, wet, 5, 3, out, touched, total, 4.0, 0.0, 1.0, every(paint))
    change, swept = new - mobile, out - mobile
    np.testing.assert_allclose(swept.sum(axis=(1, 2)), change.sum(axis=(1, 2)), rtol=1e-12)
    assert out.min() >= 0.0
    # samples at 0.5, 1.5, 2.5, 3.5 texels ahead: each the mean of two neighbours
    gain = np.maximum(change, 0.0)
    padded = np.pad(gain, ((0, 0), (0, 0), (0, 6)))
    expected = sum(padded[:, :, k : k + 50] + padded[:, :, k + 1 : k + 51] for k in range(4)) / 8
    # from texel 36 on no loss reaches (the losses at 30-35 move back to 26-35); the moved
    # fields are float32 (the canvas's own precision), their totals kept exactly
    np.testing.assert_allclose(swept[:, :, 36:], expected[:, :, 36:], rtol=F32, atol=1e-20)
    assert expected[:, :, 36:].max() > 0.0 and not np.allclose(swept, change)
    assert touched[10:20, 26:40].all() and not touched[:5].any()
    np.testing.assert_allclose(total, out.sum(axis=0), rtol=1e-12)  # all wet: no dry part


def test_losses_are_laid_as_their_mean_along_the_path_within_each_texel_s_cap():
    """Texels of unequal paint lose a patch's paint: each texel behind takes the mean of the
    losses ahead on its path (linear in the change, so the teeth of steps that repeat along a
    stroke average out), and none a larger share of its own paint than the largest share lost
    on its path. The mean of the fractions lost, times the texel's own paint, took more from
    the thicker texels and less from the thinner ones."""
    paint = np.zeros((1, 20, 40), np.float32)
    paint[0, :, :] = np.where(np.arange(40) % 2 == 0, 1e-5, 3e-5)[None, :]  # stripes of two heights
    wet = np.ones((20, 40), np.float32)
    mobile = paint[:, 2:18, 2:38].astype(np.float64)
    new = mobile.copy()
    new[:, 4:12, 20:24] *= 0.5  # half of a 4-texel patch taken
    out = new.copy()
    assert sweep_change(paint, wet, 2, 2, out, np.zeros((16, 36), bool), np.zeros((16, 36)), 4.0,
                        0.0, 1.0, every(paint))  # fmt: skip
    loss = np.maximum(mobile - new, 0.0)
    padded = np.pad(loss, ((0, 0), (0, 0), (0, 6)))
    mean = sum(padded[:, :, k : k + 36] + padded[:, :, k + 1 : k + 37] for k in range(4)) / 8
    taken = mobile - out
    np.testing.assert_allclose(taken.sum(), loss.sum(), rtol=1e-12)
    cap = 0.5 * mobile  # half: the share the patch lost, the largest on any path
    assert (taken <= cap * (1.0 + F32)).all()  # the largest share read in float32
    at_cap = np.isclose(taken, cap, rtol=F32) & (mean > 0.0)
    free = (mean > 0.0) & ~at_cap
    assert at_cap.any() and free.sum() > 20
    # below their caps the texels take the mean loss times one common scale (the water-filling's,
    # which makes up what the capped ones could not give), whatever their own paint
    ratio = taken[free] / mean[free]
    assert np.ptp(ratio) < 2.0 * F32 * ratio.mean() and ratio.mean() >= 1.0
    assert np.ptp(mobile[free]) > 1e-5  # thin and thick stripes among them


def test_losses_never_take_more_than_a_texel_holds():
    rng = np.random.default_rng(2)
    paint, wet, _, _ = canvas_and_change(rng)
    wet[13:23, 20:40] = 0.5  # half dry there: only the wet half may move
    mobile = paint[:, 3:33, 5:55].astype(np.float64) * wet[3:33, 5:55]
    new = mobile.copy()
    new[:, 10:20, 30:36] = 0.0  # all the wet paint taken, next to texels that keep theirs
    new[:, 10:20, 36:40] += 2e-5
    out = new.copy()
    sweep_change(paint, wet, 5, 3, out, np.zeros((30, 50), bool), np.zeros((30, 50)), 7.5, -2.5,
                 1.0, every(paint))  # fmt: skip
    assert out.min() >= 0.0 and not np.array_equal(out, new)
    np.testing.assert_allclose(out.sum(axis=(1, 2)), new.sum(axis=(1, 2)), rtol=1e-9)


def test_no_travel_or_a_box_cut_short_leaves_the_change_unswept():
    rng = np.random.default_rng(3)
    paint, wet, _, new = canvas_and_change(rng)
    for travel, box_x in (((0.2, 0.1), 5), ((-30.0, 0.0), 5)):  # too short; reaching past the box
        out = new.copy()
        sweep_change(paint, wet, box_x, 3, out, np.zeros((30, 50), bool), np.zeros((30, 50)),
                     *travel, 1.0, every(paint))  # fmt: skip
        np.testing.assert_array_equal(out, new)


def test_sweep_is_a_scene_switch_and_a_bad_value_names_the_key():
    assert parse_paint_scene({}, "s").sweep is True
    assert parse_paint_scene({"paint": {"sweep": False}}, "s").sweep is False
    with pytest.raises(InputError) as err:
        parse_paint_scene({"paint": {"sweep": 1}}, "s", "my_scene.toml")
    assert err.value.key == "paint.sweep" and "my_scene.toml" in str(err.value)


def test_a_sweep_that_empties_texels_still_keeps_the_loss_and_takes_no_more_than_held():
    # a long step over a thin film: the swept fractions clip in many texels (the water-filling
    # iterates), the pigment's loss is kept to round-off and no texel goes negative
    rng = np.random.default_rng(7)
    paint, wet, mobile, _ = canvas_and_change(rng, pigments=3)
    new = mobile.copy()
    new[:, 8:22, 20:34] = 0.0  # all of it taken
    new[:, 8:22, 34:38] += 4e-5
    out = new.copy()
    sweep_change(paint, wet, 5, 3, out, np.zeros((30, 50), bool), np.zeros((30, 50)), 11.0, 3.0,
                 1.0, every(paint))  # fmt: skip
    assert out.min() >= 0.0 and not np.array_equal(out, new)
    np.testing.assert_allclose(out.sum(axis=(1, 2)), new.sum(axis=(1, 2)), rtol=1e-9)


def emptied_patch():
    """A (1, 40, 60) wet canvas of uneven paint, its box at (5, 3) of (30, 50) texels, and new
    mobile paint there: a wide patch whose wet paint the brush took whole, heaped ahead."""
    rng = np.random.default_rng(1)
    paint = rng.uniform(2e-6, 2e-5, (1, 40, 60)).astype(np.float32)
    wet = np.ones((40, 60), np.float32)
    mobile = paint[:, 3:33, 5:55].astype(np.float64)
    new = mobile.copy()
    new[:, 5:25, 10:40] = 0.0
    new[:, 5:25, 40:44] += 1e-4
    return paint, wet, mobile, new


def test_a_patch_taken_up_entirely_from_uneven_paint_is_still_swept():
    # The brush lifts all the wet paint of a wide patch of uneven paint: nearly all of the loss
    # sits in texels the swept fractions empty, where the water-filling's scale converges
    # slowly by fixed-point steps (it used to stop at its cap and keep the unswept change).
    paint, wet, mobile, new = emptied_patch()
    out = new.copy()
    assert sweep_change(paint, wet, 5, 3, out, np.zeros((30, 50), bool), np.zeros((30, 50)), 5.0,
                        0.0, 1.0, every(paint))  # fmt: skip
    np.testing.assert_allclose(out.sum(), new.sum(), rtol=1e-12)
    assert out.min() >= 0.0
    # the loss laid back along the path: the texels behind the patch give paint now...
    assert np.all(out[:, 5:25, 6:10] < mobile[:, 5:25, 6:10])
    # ...and the patch's far end keeps some (its own loss moved back), none goes below zero
    assert np.all(out[:, 5:25, 36:40] > 0.0)


@pytest.mark.parametrize("travel", [(3.3, 0.1), (5.3, 0.7), (4.1, -1.3)])
def test_a_share_lost_read_above_one_takes_no_more_than_a_texel_holds(travel):
    # An emptied patch (a share lost of 1) read in float32 along a path whose bilinear weights
    # are not exact there: a share may come out a hair above 1 (it does at (3.3, 0.1)), and a
    # texel's cap is then its whole paint, not more, so the loss taken is the loss, to float64
    # round-off (unclamped, 3e-8 of it went missing at (3.3, 0.1)).
    paint, wet, _, new = emptied_patch()
    out = new.copy()
    assert sweep_change(paint, wet, 5, 3, out, np.zeros((30, 50), bool), np.zeros((30, 50)),
                        *travel, 1.0, every(paint))  # fmt: skip
    np.testing.assert_allclose(out.sum(), new.sum(), rtol=1e-12)
    assert out.min() >= 0.0


def test_a_loss_the_caps_cannot_hold_keeps_its_unswept_change():
    # Pigment 0 loses all of one texel's paint among texels holding a film a ten-thousandth as
    # thick: swept back along ten texels, the loss would have to come from the film (each
    # texel capped at its own paint) and from half of that texel's paint (the nearest sample
    # reads it with half its weight), less than the loss: no scale takes it, and the pigment
    # keeps its change as the step left it. Pigment 1's ordinary change is still swept.
    paint = np.full((2, 20, 40), 1e-9, np.float32)
    paint[0, 10, 20] = 1e-5
    paint[1] = np.random.default_rng(5).uniform(1e-6, 1e-5, (20, 40))
    wet = np.ones((20, 40), np.float32)
    mobile = paint.astype(np.float64)
    new = mobile.copy()
    new[0, 10, 20] = 0.0
    new[1, 8:12, 20:24] *= 0.5
    new[1, 8:12, 24:26] += 1e-5
    out = new.copy()
    assert sweep_change(paint, wet, 0, 0, out, np.zeros((20, 40), bool), np.zeros((20, 40)),
                        10.0, 0.0, 1.0, every(paint))  # fmt: skip
    np.testing.assert_array_equal(out[0], new[0])
    assert not np.array_equal(out[1], new[1])
    np.testing.assert_allclose(out[1].sum(), new[1].sum(), rtol=1e-9)


def test_gains_moved_along_the_path_land_where_the_tooth_takes_them():
    """A canvas tooth's gain weights (stripes taking paint three times as readily as the texels
    between them) are in the step's gains where the step laid them; moved whole along the path
    they would land off their stripes. With the weights given, the gains are moved as gains over
    weight and weighed again where they land: the stripes keep three times the paint, the total
    is kept."""
    rng = np.random.default_rng(4)
    paint, wet, mobile, new = canvas_and_change(rng, pigments=1)
    new = mobile.copy()
    stripes = np.where(np.arange(50) % 4 < 2, 1.5, 0.5)[None, :].repeat(30, axis=0)
    new[:, 8:22, 30:40] += 2e-5 * stripes[8:22, 30:40]  # a deposit on the tooth's stripes
    flat, weighed = new.copy(), new.copy()
    for out, extra in ((flat, ()), (weighed, (stripes,))):
        args = (np.zeros((30, 50), bool), np.zeros((30, 50)), 6.0, 0.0, 1.0, every(paint))
        assert sweep_change(paint, wet, 5, 3, out, *args, *extra)
        np.testing.assert_allclose(out.sum(), new.sum(), rtol=1e-12)
    gain_flat, gain_weighed = flat - mobile, weighed - mobile
    band = (slice(None), slice(10, 20), slice(26, 36))  # behind the deposit: moved paint only
    on, off = stripes[10:20, 26:36] > 1.0, stripes[10:20, 26:36] < 1.0
    assert gain_weighed[band][:, on].mean() > 2.5 * gain_weighed[band][:, off].mean()
    assert gain_flat[band][:, on].mean() < 1.5 * gain_flat[band][:, off].mean()


def test_a_long_sub_step_is_read_at_most_a_cell_apart():
    """Eight reads along a sub-step of several cells laid its change as eight copies (a fast
    stroke, a stalled window's catch-up). Short sub-steps keep at most eight reads; longer ones
    take more, never more than three spacings apart."""
    from paintapp.paint.columns_kernels import MAX_READ_GAP, MAX_SWEEP_SAMPLES, sweep_reads

    assert sweep_reads(12.0, 0.0, 3.0)[0] == 4
    assert sweep_reads(40.0, 0.0, 3.0)[0] == MAX_SWEEP_SAMPLES  # 13.3 a spacing: capped
    for travel in (80.0, 250.0, 600.0):
        samples, pad_x, _ = sweep_reads(travel, 0.3 * travel, 3.0)
        assert samples > MAX_SWEEP_SAMPLES
        assert travel / samples <= MAX_READ_GAP * 3.0
        assert pad_x == int(np.ceil(travel)) + 2
