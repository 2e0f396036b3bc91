"""The simulation worker's warm-up stroke: it compiles (or loads) what the first real stroke
needs, and leaves no trace on the canvas, the journal, the undo history or the device."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import numpy as np

from brushes import StylusSample
from paintapp.app import actions
from paintapp.app.history import copy_canvas
from paintapp.app.journal import Journal
from paintapp.app.settings import PaintSettings
from paintapp.app.shared import SharedCanvas
from paintapp.app.worker import SimulationWorker
from paintapp.canvas.model import Canvas
from tests.support.waiting import wait_for

#: Run in a fresh interpreter, where no kernel has been called yet: the compiled (or loaded)
#: signatures of every numba dispatcher of the project after the warm-up, then after real
#: strokes -- two pigments, the second through the first's wet paint -- with a haptic tip.
_SCRIPT = textwrap.dedent(
    """
    import json, sys
    import numpy as np
    from numba.core.registry import CPUDispatcher
    from brushes import StylusSample
    from paintapp.app.settings import PaintSettings, make_preset, make_scene, rebuild_session
    from paintapp.app.warmup import warm_up
    from paintapp.canvas.model import Canvas
    from paintapp.haptics.channel import ForceChannel
    from paintapp.strokes.records import LoadPigment

    def signatures():
        seen = {}
        for name, module in list(sys.modules.items()):
            if name.split(".")[0] in ("solver", "paintapp", "brushes"):
                for obj in vars(module).values():
                    if isinstance(obj, CPUDispatcher):
                        seen[id(obj)] = len(obj.signatures)
        return sum(seen.values())

    settings = PaintSettings()
    preset, scene = make_preset(settings), make_scene(settings, None)
    took = warm_up(preset, scene, (1e-4, 1e-4), "ultramarine_blue", "haptic")
    warmed = signatures()
    canvas = Canvas((600, 400), (0.06, 0.04))
    session = rebuild_session(None, canvas, preset, scene, "haptic", ForceChannel())
    t = 0.0
    depth = preset.pressure.depth_for(0.6)
    for pigment, y in (("cadmium_red", 0.02), ("titanium_white", 0.021)):
        session.handle(LoadPigment(t, pigment, 0.5 * preset.capacity_m3))
        for i in range(30):
            t += 1 / 60
            x = 0.015 + 0.03 * i / 29
            session.sample(StylusSample(t, np.array([x, y, -depth]), 0.0))
        t += 1 / 60
        session.sample(StylusSample(t, np.array([0.045, y, 0.01]), 0.0))
    print(json.dumps({
        "took": took, "warmed": warmed, "after": signatures(),
        "paint": float(canvas.paint_m.sum()), "pigments": list(canvas.pigment_names),
    }))
    """
)


def test_after_the_warm_up_the_first_strokes_compile_nothing_more():
    done = subprocess.run(
        [sys.executable, "-c", _SCRIPT], capture_output=True, text=True, timeout=900, check=True
    )
    figures = json.loads(done.stdout.strip().splitlines()[-1])
    assert figures["took"] > 0.0
    assert figures["warmed"] > 20, figures  # the warm-up did reach the kernels
    assert figures["paint"] > 0.0 and len(figures["pigments"]) == 2, figures  # real strokes
    assert figures["after"] == figures["warmed"], figures


def test_the_worker_s_warm_up_leaves_no_trace(tmp_path):
    canvas = Canvas((480, 480), (0.048, 0.048))
    shared = SharedCanvas(copy_canvas(canvas))
    record = tmp_path / "s.jsonl"
    worker = SimulationWorker(
        canvas, shared, PaintSettings(), ("cadmium_red",), Journal(record, False)
    )
    worker.start()
    try:
        assert wait_for(worker.idle.is_set, 600.0)  # the warm-up is over
        status = worker.status.get()
        assert status.fault is None and status.strokes == 0 and status.undo == 0
        assert not status.message.startswith("could not"), status.message
        assert float(canvas.paint_m.sum()) == 0.0 and canvas.pigment_names == ()
        assert shared.version == 0 and float(shared.canvas.paint_m.sum()) == 0.0
        assert worker.session.reservoir.total_m3 == 0.0  # the brush was not dipped
        assert worker.forces.latest()[1] is None  # no force was published
        worker.submit(actions.load_pigment("cadmium_red"))  # and it paints
        worker.push(StylusSample(0.0, np.array([0.02, 0.024, 0.0]), 0.8))
        worker.push(StylusSample(0.0, np.array([0.03, 0.024, 0.0]), 0.8))
        assert wait_for(lambda: worker.status.get().paint_steps > 0, 60.0)
    finally:
        worker.stop()
    lines = record.read_text().splitlines()
    assert json.loads(lines[0])["format"] == "paintapp-strokes"
    records = [json.loads(line) for line in lines[1:]]
    assert sum(1 for r in records if "pos" in r) == 2  # only the real samples
    assert [r["pigment"] for r in records if r.get("event") == "load_pigment"] == ["cadmium_red"]
