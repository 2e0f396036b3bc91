"""``paintapp export``: re-rendering and converting canvas files from the command line."""

from __future__ import annotations

import numpy as np
import OpenImageIO as oiio
import pytest

from paintapp.canvas.exr import read_canvas_exr, read_exr_rgba, unlit_rgba, write_canvas_exr
from paintapp.canvas.model import Canvas
from paintapp.cli import main
from paintapp.render import RenderUnavailable, create_headless_context


@pytest.fixture
def canvas_file(tmp_path):
    canvas = Canvas((16, 10), (0.016, 0.01))
    canvas.add_pigment("burnt_sienna")
    canvas.add_pigment("titanium_white")
    canvas.paint_m[0, :, :8] = 4e-4
    canvas.paint_m[1, 3:, :] += 2e-4 * np.linspace(0, 1, 16)
    path = tmp_path / "in.exr"
    write_canvas_exr(path, canvas, np.zeros((10, 16, 4), np.float32), half=False)
    return path, canvas


def has_gl() -> bool:
    try:
        create_headless_context().release()
    except RenderUnavailable:
        return False
    return True


def test_flat_export_to_float_exr_keeps_the_paint(canvas_file, tmp_path):
    path, canvas = canvas_file
    out = tmp_path / "out.exr"
    assert main(["export", str(path), "--out", str(out), "--float", "--flat"]) == 0
    back = read_canvas_exr(out)
    np.testing.assert_allclose(back.paint_m, canvas.paint_m, rtol=1e-6)
    np.testing.assert_allclose(read_exr_rgba(out), unlit_rgba(canvas), rtol=1e-6, atol=1e-7)


def test_png_preview_has_the_canvas_size(canvas_file, tmp_path):
    path, _ = canvas_file
    out, preview = tmp_path / "out.exr", tmp_path / "p.png"
    args = ["export", str(path), "--out", str(out), "--preview", str(preview)]
    assert main([*args, "--light-angle", "45", "--light-elevation", "30"]) == 0
    inp = oiio.ImageInput.open(str(preview))
    spec = inp.spec()
    inp.close()
    assert (spec.width, spec.height, spec.nchannels) == (16, 10, 3)
    rgba = read_exr_rgba(out)
    assert rgba[..., :3].max() > 0.1  # re-rendered, not the black picture stored in the input
    if has_gl():  # lit from the upper right: the picture differs from the unlit colour
        assert not np.allclose(rgba, unlit_rgba(read_canvas_exr(path)), atol=1e-3)


def test_keep_picture_reuses_the_stored_rgba(canvas_file, tmp_path):
    path, _ = canvas_file
    out = tmp_path / "out.exr"
    assert main(["export", str(path), "--out", str(out), "--keep-picture"]) == 0
    assert not read_exr_rgba(out)[..., :3].any()


@pytest.mark.parametrize(
    "extra",
    [["--out", "x.tif"], ["--out", "x.png", "--light-elevation", "0"], ["--pigments", "nope"]],
)
def test_bad_arguments_exit_with_status_2(canvas_file, tmp_path, capsys, extra):
    path, _ = canvas_file
    extra = [str(tmp_path / a) if a.startswith("x.") or a == "nope" else a for a in extra]
    if "--out" not in extra:
        extra += ["--out", str(tmp_path / "y.png")]
    assert main(["export", str(path), *extra]) == 2
    assert "error" in capsys.readouterr().err


def test_missing_input_is_a_clear_error(tmp_path, capsys):
    missing = tmp_path / "missing.exr"
    assert main(["export", str(missing), "--out", str(tmp_path / "o.png")]) == 2
    assert str(missing) in capsys.readouterr().err
