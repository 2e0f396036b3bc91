"""The lattice measure: a box-spread image shows its period, a smooth one does not."""

from __future__ import annotations

import numpy as np
import pytest

from paintapp.canvas.lattice import lattice_ratio, lattice_table, null_ratio


def smooth_image(n: int = 120) -> np.ndarray:
    y, x = np.mgrid[0:n, 0:n] / n
    return np.sin(7.3 * x + 2.1 * y) + np.cos(5.1 * y - 1.7 * x)


def test_a_smooth_image_has_no_lattice_at_any_period():
    table = lattice_table(smooth_image())
    assert max(table.values()) < 1.1


def test_box_blocks_show_their_period_and_a_tent_interpolation_does_not():
    rng = np.random.default_rng(0)
    k = 5
    columns = rng.random((24, 24))
    boxes = np.kron(columns, np.ones((k, k)))  # each column's value over its k x k block
    assert lattice_ratio(boxes, k) > 3.0
    centres = (np.arange(24) + 0.5) * k
    texels = np.arange(24 * k) + 0.5
    hat = np.maximum(1.0 - np.abs(texels[None, :] - centres[:, None]) / k, 0.0)
    tent = hat.T @ columns @ hat  # the same columns through the tent kernel
    inner = tent[k:-k, k:-k]
    assert lattice_ratio(inner, k) < 1.1
    assert lattice_ratio(np.dstack([inner, 2 * inner]), k) < 1.1  # colour: channels together


def test_the_floor_tells_a_few_strokes_from_a_lattice():
    """A handful of sharp-edged strokes at random places lifts the ratio at a long period above
    1.1 without any lattice, and the floor (the phases dealt at random) says so; box blocks'
    ratio stands far above their floor."""
    rng = np.random.default_rng(3)
    strokes = np.zeros((240, 240))
    for _ in range(6):
        x0, y0 = rng.integers(0, 200, 2)
        strokes[y0 : y0 + rng.integers(8, 40), x0 : x0 + rng.integers(30, 120)] += rng.random()
    ratio = lattice_ratio(strokes, 12)
    floor, share = null_ratio(strokes, 12)
    assert ratio > 1.1 and floor > 1.1  # no lattice, yet above 1.1
    assert share > 0.05  # as high as chance gives
    k = 5
    boxes = np.kron(rng.random((48, 48)), np.ones((k, k)))
    floor, share = null_ratio(boxes, k)
    assert lattice_ratio(boxes, k) > 2.0 * floor and share == 0.0
    assert null_ratio(strokes, 12) == null_ratio(strokes, 12)  # reproducible


def test_bad_periods_are_refused():
    with pytest.raises(ValueError):
        lattice_ratio(np.zeros((4, 4)), 4)


def test_holes_are_unpainted_texels_the_painting_encloses():
    from paintapp.canvas.lattice import count_holes

    height = np.zeros((40, 40))
    height[5:20, 5:20] = 1e-5
    height[10:12, 10:13] = 0.0  # a hole of 6 texels
    height[15, 15] = 5e-8  # a film under the floor is unpainted: a second hole
    height[25:35, 25:35] = 1e-5
    height[25:35, 30] = 0.0  # a cut through to the outside is no hole
    assert count_holes(height) == (7, 2)
    assert count_holes(np.zeros((8, 8))) == (0, 0)


def test_the_command_names_a_missing_folder_without_a_traceback(tmp_path, capsys):
    from paintapp.canvas.lattice import main

    assert main([str(tmp_path / "none")]) == 2
    err = capsys.readouterr().err
    assert "preview.png" in err and "demo folder" in err and "Traceback" not in err
