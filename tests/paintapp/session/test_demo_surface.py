"""``paintapp demo --surface``: the demo's canvas and servo take the surface."""

from __future__ import annotations

from paintapp.cli import main
from paintapp.resources import asset_path
from paintapp.strokes.files import read_strokes

DEMO = asset_path("strokes", "demo.jsonl")


def test_the_demo_paints_on_a_named_surface_and_feels_its_tooth():
    from paintapp.commands.demo import surface_canvas

    strokes = read_strokes(DEMO)
    assert surface_canvas(strokes, "smooth") == (None, None)  # the replay's own, as before
    canvas, servo = surface_canvas(strokes, "cotton_duck")
    assert canvas.surface == "cotton_duck" and servo.contact.surface == "cotton_duck"
    assert canvas.pixels == strokes.header.canvas.pixels
    assert canvas.pigment_names == strokes.header.pigments
    assert main(["demo", "--surface", "velvet", "--out", "unused"]) == 2
