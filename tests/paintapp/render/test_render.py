"""Rendering with moderngl (headless EGL): shaders compile, pixels match the CPU Kubelka-Munk
reference, the relief is lit from the light's side, and only dirty regions are uploaded."""

from __future__ import annotations

import numpy as np
import pytest

from paintapp.canvas.model import Canvas
from paintapp.pigments.bands import canvas_band_table, canvas_linear_rgb
from paintapp.render import (
    PROGRAM_NAMES,
    BrushOutline,
    CanvasRenderer,
    ForceArrow,
    Lighting,
    ViewRect,
    load_program,
)
from paintapp.resources import shader_source

UNLIT = Lighting(enabled=False)
TEXEL_M = 1e-4


def known_canvas(w: int = 24, h: int = 16) -> Canvas:
    """Five pigments (two texture layers): masstones, mixes, a thickness ramp and bare ground."""
    canvas = Canvas((w, h), (w * TEXEL_M, h * TEXEL_M))
    names = ["ultramarine_blue", "cadmium_yellow", "titanium_white", "cadmium_red", "phthalo_blue"]
    idx = [canvas.add_pigment(n) for n in names]
    p = canvas.paint_m
    p[idx[0], :, 0:8] = 1e-3
    p[idx[1], :, 4:12] = 1e-3
    p[idx[2], 8:, :] += 3e-4
    p[idx[3], 4:8, 14:20] = 5e-4
    p[idx[4], :, 12:14] = np.linspace(0.0, 5e-5, h)[:, None]
    p[:, :4, 20:] = 0.0  # bare ground in one corner
    return canvas


def reference(canvas: Canvas, library) -> np.ndarray:
    return canvas_linear_rgb(canvas, canvas_band_table(canvas, library))


def assert_matches(rgba: np.ndarray, expected: np.ndarray) -> None:
    # Concentrations travel as half floats: allow ~1e-3 relative plus a small absolute slack.
    np.testing.assert_allclose(rgba[..., :3], expected, rtol=1e-2, atol=2e-3)


def test_every_shader_file_is_a_known_program():
    import importlib.resources

    files = {p.name for p in importlib.resources.files("paintapp.shaders").iterdir()}
    assert {f"{n}.glsl" for n in PROGRAM_NAMES} == {f for f in files if f.endswith(".glsl")}
    for name in PROGRAM_NAMES:
        source_lines = shader_source(f"{name}.glsl").splitlines()
        assert not any(line.startswith("#version") for line in source_lines)  # the loader adds it


@pytest.mark.parametrize("name", PROGRAM_NAMES)
def test_every_shader_compiles(ctx, name):
    variants = [{"N_GROUPS": 3, "MAX_PIGMENTS": 16, "N_LAYERS": n} for n in (1, 4)]
    for defines in variants if name == "canvas" else [None]:
        program = load_program(ctx, name, defines)
        assert "u_view" in program
        program.release()


def test_render_matches_the_cpu_reference_pixel_by_pixel(ctx, library):
    canvas = known_canvas()
    renderer = CanvasRenderer(ctx, library, lighting=UNLIT)
    rgba = renderer.render_linear_rgba(canvas)
    assert rgba.shape == (16, 24, 4) and np.all(rgba[..., 3] == 1.0)
    assert_matches(rgba, reference(canvas, library))
    renderer.release()


def test_flat_dry_paint_keeps_its_colour_under_any_light(ctx, library):
    canvas = known_canvas()
    total = canvas.height_m
    canvas.paint_m *= np.where(total > 0, 1e-3 / np.maximum(total, 1e-30), 0.0)
    canvas.paint_m[0][total == 0] = 1e-3  # a flat 1 mm surface everywhere
    canvas.mark_all_dirty()
    expected = reference(canvas, library)
    renderer = CanvasRenderer(ctx, library)
    for azimuth, elevation in ((135.0, 45.0), (10.0, 20.0)):
        renderer.lighting = Lighting(azimuth_deg=azimuth, elevation_deg=elevation, specular=0.0)
        assert_matches(renderer.render_linear_rgba(canvas), expected)
    renderer.release()


def ridge_canvas(wet: float = 0.0) -> Canvas:
    canvas = Canvas((32, 8), (32 * TEXEL_M, 8 * TEXEL_M))
    canvas.add_pigment("titanium_white")
    x = np.arange(32)
    canvas.paint_m[0] = (2e-3 + 3e-4 * np.exp(-(((x - 16) / 4.0) ** 2)))[None, :]
    canvas.wetness[:] = wet
    return canvas


def test_impasto_relief_is_lit_from_the_light_side(ctx, library):
    canvas = ridge_canvas()
    renderer = CanvasRenderer(ctx, library)
    lum = {}
    for azimuth in (180.0, 0.0):  # light from -x (left), then from +x (right)
        renderer.lighting = Lighting(azimuth_deg=azimuth, elevation_deg=30.0, specular=0.0)
        canvas.mark_all_dirty()
        lum[azimuth] = renderer.render_linear_rgba(canvas)[4, :, 1]
    left_flank, right_flank, far = 13, 19, 0
    assert lum[180.0][left_flank] > lum[180.0][far] > lum[180.0][right_flank]
    assert lum[0.0][right_flank] > lum[0.0][far] > lum[0.0][left_flank]
    renderer.release()


def test_wet_paint_has_a_specular_highlight(ctx, library):
    renderer = CanvasRenderer(ctx, library)
    renderer.lighting = Lighting(elevation_deg=90.0, specular=0.4)
    dry = renderer.render_linear_rgba(ridge_canvas(wet=0.0))
    wet = renderer.render_linear_rgba(ridge_canvas(wet=1.0))
    assert wet[4, 0, :3] - dry[4, 0, :3] == pytest.approx([0.4] * 3, abs=1e-3)  # flat: n.h = 1
    renderer.release()


def test_only_the_dirty_region_is_uploaded(ctx, library):
    canvas = known_canvas()
    renderer = CanvasRenderer(ctx, library, lighting=UNLIT)
    before = renderer.render_linear_rgba(canvas)
    assert renderer.update(canvas) is None  # nothing changed
    red = canvas.pigment_index("cadmium_red")
    canvas.paint_m[red, 0:2, 0:2] = 2e-3  # changed without telling anyone
    patch = np.zeros((5, 3, 3), np.float32)
    patch[red] = 1e-3
    canvas.write_region(20, 0, patch)  # the proper way: marks (20, 0, 23, 3) dirty
    assert renderer.update(canvas) == (20, 0, 23, 3)
    renderer.render()
    after = renderer.read_linear_rgba()
    np.testing.assert_array_equal(after[0:2, 0:2], before[0:2, 0:2])  # not re-uploaded
    assert_matches(after[0:3, 20:23], reference(canvas, library)[0:3, 20:23])
    assert not np.allclose(after[0:3, 20:23], before[0:3, 20:23])
    renderer.release()


def test_a_new_pigment_rebuilds_the_textures(ctx, library):
    canvas = Canvas((8, 8), (8 * TEXEL_M, 8 * TEXEL_M))
    canvas.add_pigment("cadmium_yellow")
    renderer = CanvasRenderer(ctx, library, lighting=UNLIT)
    renderer.render_linear_rgba(canvas)
    canvas.add_pigment("ivory_black")  # fits the first layer: nothing to upload
    assert renderer.update(canvas) is None
    for name in ("ivory_black", "sap_green", "burnt_sienna", "quinacridone_magenta"):
        canvas.write_region(0, 0, np.full((canvas.add_pigment(name) + 1, 8, 2), 2e-4))
    assert_matches(renderer.render_linear_rgba(canvas), reference(canvas, library))
    renderer.release()


def test_view_rect_shows_a_part_of_the_canvas(ctx, library):
    canvas = known_canvas()
    renderer = CanvasRenderer(ctx, library, lighting=UNLIT)
    view = ViewRect(8 * TEXEL_M, 4 * TEXEL_M, 20 * TEXEL_M, 12 * TEXEL_M)
    rgba = renderer.render_linear_rgba(canvas, size=(12, 8), view=view)
    assert_matches(rgba, reference(canvas, library)[4:12, 8:20])
    renderer.release()


def test_brush_outline_and_force_arrow_are_drawn(ctx, library):
    canvas = Canvas((64, 64), (64 * TEXEL_M, 64 * TEXEL_M))
    renderer = CanvasRenderer(ctx, library, lighting=UNLIT)
    centre = (32.0 * TEXEL_M, 32.0 * TEXEL_M)
    outline = BrushOutline(centre, (10 * TEXEL_M, 10 * TEXEL_M), color=(0.0, 0.0, 1.0, 1.0))
    arrow = ForceArrow(centre, (2.0, 0.0, 5.0), 10 * TEXEL_M, color=(1.0, 0.0, 0.0, 1.0))
    renderer.update(canvas)
    renderer.render(outlines=[outline], arrows=[arrow])
    rgba = renderer.read_linear_rgba()
    ground = rgba[5, 5, :3].copy()
    assert rgba[32, 12 + 10, :3] == pytest.approx([0.0, 0.0, 1.0])  # on the ring, left side
    assert rgba[32 + 10, 32, :3] == pytest.approx([0.0, 0.0, 1.0])  # top of the ring
    assert rgba[32, 40, :3] == pytest.approx([1.0, 0.0, 0.0])  # along +x: the arrow (20 texels)
    assert rgba[32, 26, :3] == pytest.approx(ground)  # behind the tail: untouched
    assert rgba[36, 32, :3] == pytest.approx(ground)  # inside the ring, off the arrow
    renderer.release()


def test_largest_canvas_uploads_and_renders(ctx, library):
    canvas = Canvas((4096, 4096), (0.4, 0.4))
    red = canvas.add_pigment("cadmium_red")
    canvas.paint_m[red, 4000:4090, 4000:4050] = 1e-3
    renderer = CanvasRenderer(ctx, library, lighting=UNLIT)
    assert renderer.update(canvas) == (0, 0, 4096, 4096)
    view = ViewRect(3990 * 1e-4 * 0.9765625, 3990 * 1e-4 * 0.9765625, 0.4, 0.4)
    renderer.render(size=(106, 106), view=view)
    rgba = renderer.read_linear_rgba()
    expected = canvas_linear_rgb(canvas, canvas_band_table(canvas, library), slice(3990, 4096))
    assert_matches(rgba, expected[:, 3990:])
    renderer.release()


@pytest.mark.parametrize("zero_fill", [False, True])
@pytest.mark.parametrize("reduction", [1, 4])
def test_dirty_region_uploads_equal_a_full_upload(ctx, library, monkeypatch, zero_fill, reduction):
    from paintapp.render import textures

    if zero_fill:  # every box is large: zeroed first, only its painted part computed
        monkeypatch.setattr(textures, "ZERO_FILL_TEXELS", 1)
    rng = np.random.default_rng(11)
    names = ("cadmium_red", "cadmium_yellow", "ultramarine_blue", "titanium_white", "ivory_black")
    canvas = Canvas((300, 200), (300 * TEXEL_M, 200 * TEXEL_M), names)
    live = CanvasRenderer(ctx, library, lighting=UNLIT)
    live.reduction = reduction
    live.update(canvas)
    for _ in range(12):  # strokes here and there, and the paint drying in between
        w, h = rng.integers(1, 60, 2)
        x0, y0 = rng.integers(-20, 290), rng.integers(-20, 190)
        patch = rng.uniform(0.0, 1e-3, (len(names), h, w)).astype(np.float32)
        canvas.write_region(int(x0), int(y0), patch, np.ones((h, w), np.float32))
        canvas.dry(5.0, 0.01)
        live.update(canvas)
    assert canvas.peek_dirty() is None and canvas.peek_wet_dirty() is None
    fresh = CanvasRenderer(ctx, library, lighting=UNLIT)
    fresh.reduction = reduction
    canvas.mark_all_dirty()
    assert fresh.update(canvas) == (0, 0, 300, 200)
    for a, b in (
        (live._textures.concentration, fresh._textures.concentration),
        (live._textures.surface, fresh._textures.surface),
    ):
        assert a.read() == b.read()
    live.release()
    fresh.release()


def _cached(renderer: CanvasRenderer, canvas: Canvas) -> tuple[np.ndarray, object]:
    """The cached-picture render of the whole canvas at one pixel per texel, read back."""
    renderer.update(canvas)
    shaded = renderer.render_cached(canvas.pixels, ViewRect.whole(canvas.size_m))
    return renderer.read_linear_rgba(), shaded


def test_cached_picture_render_matches_the_direct_render(ctx, library):
    canvas = known_canvas()
    lit = Lighting(enabled=True, relief=50.0)
    direct = CanvasRenderer(ctx, library, lighting=lit)
    exact = direct.render_linear_rgba(known_canvas())
    cached = CanvasRenderer(ctx, library, lighting=lit)
    rgba, shaded = _cached(cached, canvas)
    assert shaded == (0, 0, *canvas.pixels)  # the first frame shades everything
    # the picture is half floats: the direct render's values within half-float rounding
    np.testing.assert_allclose(rgba[..., :3], exact[..., :3], rtol=2e-3, atol=1e-4)
    direct.release()
    cached.release()


def test_cached_picture_reshades_only_what_changed_and_stays_exact(ctx, library):
    canvas = known_canvas()
    lit = Lighting(enabled=True, relief=50.0)
    cached = CanvasRenderer(ctx, library, lighting=lit)
    _cached(cached, canvas)
    _, shaded = _cached(cached, canvas)
    assert shaded is None  # nothing changed: a frame is a blit
    for c in (canvas, reference_canvas := known_canvas()):
        c.paint_m[0, 5:8, 10:13] += 4e-4  # a dab (rows 5-7, columns 10-12)
    canvas.mark_dirty(10, 5, 13, 8)
    rgba, shaded = _cached(cached, canvas)
    assert shaded == (9, 4, 14, 9)  # the dab and the texel round it that its relief lights
    fresh = CanvasRenderer(ctx, library, lighting=lit)
    exact = fresh.render_linear_rgba(reference_canvas)
    np.testing.assert_allclose(rgba[..., :3], exact[..., :3], rtol=2e-3, atol=1e-4)
    cached.lighting = Lighting(enabled=True, relief=50.0, azimuth_deg=200.0)
    _, shaded = _cached(cached, canvas)
    assert shaded == (0, 0, *canvas.pixels)  # a new light reshades everything
    fresh.release()
    cached.release()


def test_gl_finish_waits_for_the_rasterizer_with_the_interpreter_lock_released(ctx, library):
    """The window's read-back waits in :func:`gl_finish`: the picture is complete after it, and
    another Python thread (the simulation worker) keeps running while the rasterizer works."""
    import threading
    import time

    from paintapp.render.finish import gl_finish

    canvas = known_canvas(1200, 800)
    renderer = CanvasRenderer(ctx, library, lighting=UNLIT)
    renderer.update(canvas)
    renderer.render()
    ctx.finish()  # programs and textures ready: what follows times one render
    counted, stop = [0], threading.Event()

    def count() -> None:
        while not stop.is_set():
            counted[0] += 1

    worker = threading.Thread(target=count)
    worker.start()
    time.sleep(0.05)
    try:
        before, begin = counted[0], time.perf_counter()
        time.sleep(0.05)  # the pace of the other thread while this one holds no lock
        free_rate = (counted[0] - before) / (time.perf_counter() - begin)
        renderer.render()  # queued; the software rasterizer shades at the finish
        before = counted[0]
        begin = time.perf_counter()
        assert gl_finish()
        waited = time.perf_counter() - begin
        during = counted[0] - before
    finally:
        stop.set()
        worker.join()
    assert waited > 0.005, f"nothing left to wait for ({1e3 * waited:.2f} ms): cannot tell"
    # Held, the lock would let the other thread run a few switch intervals at most (~3 % of
    # its free pace here); released, it shares the cores with the rasterizer (20-40 %).
    share = during / waited / free_rate
    assert share > 0.1, f"the other thread ran at {100 * share:.1f} % of its pace meanwhile"
    rgba = renderer.read_linear_rgba()
    crop = Canvas((24, 16), (24 * TEXEL_M, 16 * TEXEL_M), canvas.pigment_names)
    crop.paint_m[:] = canvas.paint_m[:, :16, :24]
    assert_matches(rgba[:16, :24], reference(crop, library))
    renderer.release()


def test_packing_a_region_gives_the_canvas_concentrations_and_height_exactly():
    from paintapp.render.textures import block_means, layer_count, pack_region

    rng = np.random.default_rng(7)
    canvas = known_canvas(40, 30)
    canvas.paint_m[:] *= rng.uniform(0.0, 2.0, canvas.paint_m.shape).astype(np.float32)
    canvas.paint_m[:, 3:6, 10:20] = 0.0  # bare texels
    canvas.wetness[:] = rng.uniform(0.0, 1.0, canvas.wetness.shape).astype(np.float32)
    box = (7, 4, 33, 25)
    x0, y0, x1, y1 = box
    layers = layer_count(len(canvas.pigment_names))
    conc = np.full((layers, y1 - y0, x1 - x0, 4), np.nan, np.float32)
    surface = np.full((y1 - y0, x1 - x0, 2), np.nan, np.float32)
    pack_region(canvas.paint_m, 1, x0, y0, conc, surface[..., 0])
    block_means(canvas.wetness, 1, x0, y0, surface[..., 1])
    expected = np.zeros((4 * layers, y1 - y0, x1 - x0), np.float32)
    expected[: len(canvas.pigment_names)] = canvas.concentration_region(box)
    got = conc.transpose(0, 3, 1, 2).reshape(4 * layers, y1 - y0, x1 - x0)
    assert np.array_equal(got, expected)
    height = canvas.paint_m[:, y0:y1, x0:x1].sum(axis=0, dtype=np.float32)
    assert np.array_equal(surface[..., 0], height)
    assert np.array_equal(surface[..., 1], canvas.wetness[y0:y1, x0:x1])


def test_reduced_textures_hold_the_block_means_of_the_canvas():
    """A reduction f packs each f x f block (fewer texels at the far edges) as one texel: the
    pigments' and the wetness's means, and fractions and height from those means."""
    from paintapp.render.textures import block_means, layer_count, pack_region

    rng = np.random.default_rng(11)
    canvas = known_canvas(37, 22)  # not a multiple of the block at either edge
    canvas.paint_m[:] *= rng.uniform(0.0, 2.0, canvas.paint_m.shape).astype(np.float32)
    canvas.wetness[:] = rng.uniform(0.0, 1.0, canvas.wetness.shape).astype(np.float32)
    f, layers = 4, layer_count(len(canvas.pigment_names))
    w, h = -(-37 // f), -(-22 // f)
    conc = np.zeros((layers, h, w, 4), np.float32)
    surface = np.zeros((h, w, 2), np.float32)
    pack_region(canvas.paint_m, f, 0, 0, conc, surface[..., 0])
    block_means(canvas.wetness, f, 0, 0, surface[..., 1])
    for j, i in ((0, 0), (2, 3), (h - 1, w - 1), (h - 1, 0)):
        block = (slice(j * f, (j + 1) * f), slice(i * f, (i + 1) * f))
        means = canvas.paint_m[(slice(None), *block)].astype(np.float64).mean(axis=(1, 2))
        total = means.sum()
        np.testing.assert_allclose(surface[j, i, 0], total, rtol=1e-6)
        np.testing.assert_allclose(surface[j, i, 1], canvas.wetness[block].mean(), rtol=1e-6)
        got = conc.transpose(0, 3, 1, 2).reshape(4 * layers, h, w)[: len(means), j, i]
        np.testing.assert_allclose(got, means / total, rtol=1e-5)


def test_a_reduced_renderer_draws_a_blocky_canvas_as_the_full_one_does(ctx, library):
    """Paint uniform over 4 x 4 blocks: drawn from textures reduced 4 times, at one pixel per
    block, the picture is the full-resolution one's."""
    rng = np.random.default_rng(5)
    blocks = known_canvas(12, 8)
    blocks.paint_m[:] *= rng.uniform(0.5, 1.5, blocks.paint_m.shape).astype(np.float32)
    canvas = Canvas((48, 32), (48 * TEXEL_M, 32 * TEXEL_M), blocks.pigment_names)
    canvas.paint_m[:] = np.repeat(np.repeat(blocks.paint_m, 4, axis=1), 4, axis=2)
    pictures = []
    for reduction in (1, 4):
        renderer = CanvasRenderer(ctx, library, lighting=UNLIT)
        renderer.reduction = reduction
        canvas.mark_all_dirty()
        renderer.update(canvas)
        renderer.render(size=(12, 8))
        pictures.append(renderer.read_linear_rgba())
        renderer.release()
    np.testing.assert_allclose(pictures[1], pictures[0], rtol=2e-3, atol=1e-4)
    assert_matches(pictures[1], reference(blocks, library))


def test_overlay_triangles_are_kept_read_only_and_equal_a_fresh_build():
    from paintapp.render.overlays import (
        _arrow_triangles,
        _outline_triangles,
        arrow_triangles,
        outline_triangles,
    )

    outline = BrushOutline((0.031, 0.047), (0.004, 0.003), 0.3)
    first = outline_triangles(outline, 1e-4)
    again = outline_triangles(BrushOutline((0.031, 0.047), (0.004, 0.003), 0.3), 1e-4)
    assert again is first and not first.flags.writeable
    np.testing.assert_array_equal(first, _outline_triangles(outline, 1e-4))
    moved = outline_triangles(BrushOutline((0.032, 0.047), (0.004, 0.003), 0.3), 1e-4)
    np.testing.assert_allclose(moved - first, np.tile([0.001, 0.0], (len(first), 1)), atol=1e-7)
    arrow = ForceArrow((0.03, 0.04), (0.01, -0.02, 0.0), 0.5)
    np.testing.assert_array_equal(arrow_triangles(arrow, 1e-4), _arrow_triangles(arrow, 1e-4))
    # fields that cannot be hashed (arrays) are built anew, with the same values
    loose = BrushOutline(np.array([0.031, 0.047]), (0.004, 0.003), 0.3)  # type: ignore[arg-type]
    np.testing.assert_array_equal(outline_triangles(loose, 1e-4), first)
