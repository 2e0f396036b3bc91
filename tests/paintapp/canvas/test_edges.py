"""The edge width: hard, ramped and blurred edges of known width; no paint; the command."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest
from scipy.ndimage import gaussian_filter

from paintapp.canvas.edges import (
    edge_width,
    local_edge_width,
    main,
    paint_edge_width,
    paint_edge_widths,
)
from paintapp.canvas.model import Canvas

H_M = 2e-4  # plateau thickness, m


def radius(n: int, centre: tuple[float, float]) -> np.ndarray:
    """Distance (texels) of each texel centre of an n x n canvas from ``centre``."""
    y, x = np.mgrid[0:n, 0:n] + 0.5
    return np.hypot(x - centre[0], y - centre[1])


def disc(n: int, r: float, ramp: float = 0.0, centre: tuple[float, float] | None = None):
    """A disc of thickness H_M out to ``r`` texels, falling linearly to 0 over ``ramp`` more."""
    dist = radius(n, centre or (0.5 * n + 0.3, 0.5 * n - 0.2))
    if ramp == 0.0:
        return np.where(dist <= r, H_M, 0.0)
    return H_M * np.clip(1.0 - (dist - r) / ramp, 0.0, 1.0)


def test_a_hard_edge_has_no_width():
    result = edge_width(disc(200, 60.0))
    assert result.t90_m == H_M and result.ramp_texels == 0
    assert result.contour_texels > 300 and result.width_texels < 1.0


def test_a_straight_linear_ramp_over_n_texels_measures_0_45_n():
    """Texel i (centre i + 0.5) of a ramp over N = 20 texels holds 1 - (i + 0.5) / N of the
    plateau: i = 10..18 lie in [0.05, 0.5], 9 = 0.45 N texels per row on each side, and each
    row has one contour texel on each side (the canvas's own border is no contour)."""
    n_ramp, rows = 20, 30
    x = np.arange(200) + 0.5
    profile = H_M * np.clip(np.minimum(x - 40.0, 160.0 - x) / n_ramp, 0.0, 1.0)
    result = edge_width(np.tile(profile, (rows, 1)))
    assert result.t90_m == H_M
    assert (result.ramp_texels, result.contour_texels) == (2 * 9 * rows, 2 * rows)
    assert result.width_texels == pytest.approx(0.45 * n_ramp)


@pytest.mark.parametrize("n_ramp", [6.0, 10.0, 16.0])
def test_a_disc_with_a_linear_ramp_measures_what_the_definition_gives(n_ramp):
    """A disc of radius R whose edge falls linearly over N texels: the ramp texels
    (thickness in [0.05, 0.5] x T90) fill the annulus R + 0.5 N <= r <= R + 0.95 N, area
    pi 0.45 N (2 R + 1.45 N); the contour texels of a digital circle of radius
    rho = R + 0.5 N number 4 sqrt(2) rho (a slanted edge at angle a counts max(|cos a|,
    |sin a|) texels per texel of length). So the width is 0.45 N (2 R + 1.45 N) pi /
    (4 sqrt(2) (R + 0.5 N)), about 0.5 N: the 0.45 N of a straight edge times pi / (2 sqrt(2))
    and the annulus's widening."""
    r = 60.0
    result = edge_width(disc(220, r, n_ramp))
    assert result.t90_m == pytest.approx(H_M)  # most painted texels are on the plateau
    area = math.pi * 0.45 * n_ramp * (2 * r + 1.45 * n_ramp)
    contour = 4 * math.sqrt(2) * (r + 0.5 * n_ramp)
    assert result.ramp_texels == pytest.approx(area, rel=0.02)
    assert result.contour_texels == pytest.approx(contour, rel=0.02)
    assert result.width_texels == pytest.approx(area / contour, rel=0.03)
    assert 0.45 * n_ramp < result.width_texels < 0.56 * n_ramp


def test_a_blurred_edge_measures_wider_than_a_sharp_one():
    sharp = disc(200, 60.0)
    widths = [edge_width(gaussian_filter(sharp, sigma)).width_texels for sigma in (1.0, 3.0)]
    assert edge_width(sharp).width_texels < 1.0 < widths[0] < widths[1]
    # a Gaussian edge of sigma s has its 5-50 % band over 1.645 s: about that, times ~1.1
    assert widths[1] == pytest.approx(1.645 * 3.0 * math.pi / (2 * math.sqrt(2)), rel=0.1)


def test_no_paint_has_no_edge_and_no_division_by_zero():
    """No painted texel (or only films under 0.1 um): no T90 and no contour, so the width is
    NaN (0 would claim a perfectly sharp edge); even paint everywhere has no contour."""
    for thickness in (np.zeros((40, 50)), np.full((40, 50), 5e-8)):
        result = edge_width(thickness)
        assert math.isnan(result.width_texels) and not result.has_edge
        assert (result.t90_m, result.ramp_texels, result.contour_texels) == (0.0, 0, 0)
        assert "none" in result.describe()
    even = edge_width(np.full((40, 50), 1e-4))
    assert math.isnan(even.width_texels) and even.contour_texels == 0 and even.t90_m == 1e-4


def test_the_paint_of_all_pigments_counts_together():
    thickness = disc(120, 30.0, 8.0)
    split = np.stack([0.25 * thickness, 0.75 * thickness])
    assert paint_edge_width(split).width_texels == pytest.approx(
        edge_width(thickness).width_texels, rel=1e-12
    )
    with pytest.raises(ValueError):
        edge_width(split)


def test_the_command_prints_the_edge_width_of_a_canvas_file(tmp_path, capsys):
    from paintapp.canvas.exr import read_canvas_exr, write_canvas_exr

    x = np.arange(120) + 0.5
    profile = 1e-4 * np.clip(np.minimum(x - 20.0, 100.0 - x) / 20.0, 0.0, 1.0)
    height = np.tile(profile, (16, 1)).astype(np.float32)
    canvas = Canvas((120, 16), (0.012, 0.0016), ("cadmium_red", "titanium_white"))
    canvas.paint_m[0], canvas.paint_m[1] = 0.5 * height, 0.5 * height
    write_canvas_exr(tmp_path / "canvas.exr", canvas, np.ones((16, 120, 4)), half=False)
    assert main([str(tmp_path)]) == 0
    out = capsys.readouterr().out.splitlines()
    read, local = paint_edge_widths(read_canvas_exr(tmp_path / "canvas.exr").paint_m)
    assert read.width_texels == pytest.approx(9.0)  # a straight ramp over 20 texels: 0.45 N
    assert out == [read.describe(1e-4), local.describe(1e-4)]
    assert out[0].startswith("edge width 9 texels (0.9 mm)")
    assert out[1].startswith("local edge width 9 texels (0.9 mm)")


def test_the_command_names_a_missing_or_bad_folder_in_one_line(tmp_path, capsys):
    assert main([str(tmp_path / "none")]) == 2
    err = capsys.readouterr().err
    assert "canvas.exr" in err and "demo folder" in err and err.count("\n") == 1
    (tmp_path / "canvas.exr").write_bytes(b"not an image")
    run = subprocess.run(
        [sys.executable, "-m", "paintapp.canvas.edges", str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert run.returncode == 2 and run.stdout == ""
    assert run.stderr.startswith("edges: error: ") and run.stderr.count("\n") == 1
    assert "Traceback" not in run.stderr and "demo folder" in run.stderr


def strips(plateaus: tuple[float, ...], ramp: float, n: int = 400) -> np.ndarray:
    """Horizontal strips 60 texels wide, 100 texels apart, each of its own plateau thickness,
    falling linearly to 0 over ``ramp`` texels on both sides."""
    y = np.arange(n) + 0.5
    column = np.zeros(n)
    for k, plateau in enumerate(plateaus):
        centre = 60.0 + 120.0 * k
        inside = np.clip(1.0 - (np.abs(y - centre) - 30.0) / ramp, 0.0, 1.0)
        column += plateau * inside
    return np.tile(column[:, None], (1, 300))


def test_the_local_measure_reads_one_thickness_as_the_global_one():
    thickness = strips((H_M, H_M, H_M), 20.0)
    assert local_edge_width(thickness).width_texels == pytest.approx(
        edge_width(thickness).width_texels, rel=0.02
    )
    assert local_edge_width(thickness).width_texels == pytest.approx(9.0, rel=0.05)


def test_the_local_measure_takes_a_thin_strokes_body_for_a_body():
    """Strips of 1, 1/4 and 1 plateau with the same 20-texel ramps: the global T90 is the thick
    ones', so the thin strip's whole body counts as ramp; against the local scale each edge
    measures about 0.45 N (more where a tile's block holds both thicknesses)."""
    thickness = strips((H_M, 0.25 * H_M, H_M), 20.0)
    globally, locally = edge_width(thickness), local_edge_width(thickness)
    assert globally.width_texels > 15.0
    assert locally.width_texels == pytest.approx(9.0, rel=0.15)
    assert locally.local and not globally.local
    assert "local T90" in locally.describe() and locally.t90_m == globally.t90_m


def test_the_local_measure_without_paint_or_edge():
    assert math.isnan(local_edge_width(np.zeros((50, 60))).width_texels)
    assert math.isnan(local_edge_width(np.full((50, 60), 1e-4)).width_texels)
