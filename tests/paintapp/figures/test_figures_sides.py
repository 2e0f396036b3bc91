"""``paintapp figures sides``: the four drags' plot and figures; bad outputs refused first."""

from __future__ import annotations

import pytest

from paintapp.cli import main
from paintapp.figures import sides


def test_the_figure_is_written_with_a_line_per_grid(tmp_path, capsys, monkeypatch):
    short = list(sides.CASES)
    short[-1] = ("slip walls, 48 cells (reference)", "slip", 48, 3.0, "cells")  # faster than 64
    monkeypatch.setattr(sides, "CASES", tuple(short))
    out = tmp_path / "sides.png"
    assert main(["figures", "sides", "--out", str(out)]) == 0
    assert out.stat().st_size > 10_000 and out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    printed = capsys.readouterr().out
    for label, *_ in short:
        assert label in printed
    assert "wrote" in printed


@pytest.mark.parametrize("name", ["sides.jpg", "missing/deeper/sides.png"])
def test_a_bad_output_is_refused_before_any_drag(tmp_path, capsys, monkeypatch, name):
    monkeypatch.setattr(sides, "drag", lambda *a: pytest.fail("dragged before checking --out"))
    target = tmp_path / "taken"
    target.write_text("x")  # a file where a folder is due
    path = target / name if "/" in name else tmp_path / name
    assert main(["figures", "sides", "--out", str(path)]) == 2
    assert "--out" in capsys.readouterr().err
