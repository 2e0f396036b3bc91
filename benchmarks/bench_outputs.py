"""The files `paintapp demo` writes after its painting: the canvas EXR, alone and with the rest.

Builds a canvas of the demo's size (A4 at 0.1 mm, 2100 x 2970 texels, four pigments) with smooth
random paint and wetness, and times, alternately in one process, the committed tree's way
(``git show <rev>:paintapp/canvas/exr.py`` and ``.../session/outputs.py`` loaded as modules) and
the working tree's way of

- ``write_canvas_exr`` with a fixed picture (``exr`` rows), and
- ``write_canvas_outputs`` (the lit picture, the EXR and the PNG preview; ``outputs`` rows),

each written into a temporary folder, then prints the medians and the files' sizes. The files of
both ways are read back with OpenImageIO and compared channel by channel (they must be equal, bit
for bit).

    python benchmarks/bench_outputs.py [--rounds 5] [--rev HEAD] [--no-outputs]
        [--exr-threads N] [--surface NAME]
    python benchmarks/bench_outputs.py --overlap-probe [--rounds 5]

``--exr-threads`` adds an ``exr`` row of the working tree's way with that many OpenEXR threads
(``paintapp.canvas.exr.EXR_THREADS``; 0 compresses on the calling thread). ``--overlap-probe``
times only the lit picture and the EXR's channels, one after the other and on two threads side
by side.
"""

from __future__ import annotations

import argparse
import importlib.util
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from pathlib import Path
from types import ModuleType

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from paintapp.canvas import exr as new_exr  # noqa: E402
from paintapp.canvas.model import Canvas  # noqa: E402
from paintapp.session import outputs as new_outputs  # noqa: E402

PIGMENTS = ("ultramarine_blue", "cadmium_yellow", "titanium_white", "cadmium_red")
PIXELS, SIZE_M = (2100, 2970), (0.210, 0.297)


def committed_module(rev: str, relpath: str, name: str, tmp: Path) -> ModuleType:
    """``relpath`` as it is in git revision ``rev``, loaded as module ``name``."""
    source = subprocess.run(
        ["git", "show", f"{rev}:{relpath}"], cwd=ROOT, check=True, capture_output=True, text=True
    ).stdout
    path = tmp / f"{name}.py"
    path.write_text(source)
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def smooth_field(rng: np.random.Generator, shape: tuple[int, int], cells: int = 24) -> np.ndarray:
    """A smooth random field in [0, 1] of ``shape`` (bilinear over a coarse random grid)."""
    coarse = rng.uniform(0.0, 1.0, (cells + 1, cells + 1))
    y = np.linspace(0, cells, shape[0])
    x = np.linspace(0, cells, shape[1])
    y0 = np.minimum(y.astype(int), cells - 1)
    x0 = np.minimum(x.astype(int), cells - 1)
    fy, fx = (y - y0)[:, None], (x - x0)[None, :]
    c = coarse
    top = c[y0][:, x0] * (1 - fx) + c[y0][:, x0 + 1] * fx
    bottom = c[y0 + 1][:, x0] * (1 - fx) + c[y0 + 1][:, x0 + 1] * fx
    return (top * (1 - fy) + bottom * fy).astype(np.float32)


def painted_canvas(surface: str) -> Canvas:
    """The demo's canvas with smooth random paint (up to 0.2 mm a pigment, bare where the
    paint would be under 5 um) and wetness."""
    rng = np.random.default_rng(7)
    canvas = Canvas(PIXELS, SIZE_M, PIGMENTS, surface=surface)
    shape = (canvas.height, canvas.width)
    for i in range(len(PIGMENTS)):
        paint = 2e-4 * smooth_field(rng, shape) ** 2
        paint[paint < 5e-6] = 0.0
        canvas.paint_m[i] = paint
    canvas.wetness[:] = smooth_field(rng, shape)
    return canvas


def picture(canvas: Canvas) -> np.ndarray:
    """A fixed linear RGBA picture, (H, W, 4) float32, some of it above half's largest value."""
    rng = np.random.default_rng(8)
    rgba = np.ones((canvas.height, canvas.width, 4), np.float32)
    for i in range(3):
        rgba[..., i] = smooth_field(rng, (canvas.height, canvas.width))
    return rgba


def timed(fn: Callable[[], object]) -> float:
    start = time.perf_counter()
    fn()
    return time.perf_counter() - start


def patched(module: ModuleType, name: str, value: object, fn: Callable[[], None]) -> None:
    """Run ``fn`` with ``module.name`` set to ``value``."""
    real = getattr(module, name)
    setattr(module, name, value)
    try:
        fn()
    finally:
        setattr(module, name, real)


def overlap_probe(canvas: Canvas, rounds: int) -> None:
    """The lit picture and the EXR's channels (the picture's channels zero), one
    after the other and side by side on two threads: whether the render leaves room for them."""
    rgba = np.zeros((canvas.height, canvas.width, 4), np.float32)
    names = ("R", "G", "B", "A", new_exr.HEIGHT, new_exr.WETNESS)
    names += tuple(map(new_exr.pigment_channel, canvas.pigment_names))
    names += (new_exr.TOOTH,) if canvas.has_tooth else ()

    def prepare() -> None:
        new_exr.file_channels(canvas, rgba, names, True)

    def side_by_side() -> None:
        thread = threading.Thread(target=prepare)
        thread.start()
        new_outputs.canvas_picture(canvas)
        thread.join()

    new_outputs.canvas_picture(canvas)  # the first context and shaders
    times: dict[str, list[float]] = {"picture": [], "paint channels": [], "side by side": []}
    for _ in range(rounds):
        times["picture"].append(timed(lambda: new_outputs.canvas_picture(canvas)))
        times["paint channels"].append(timed(prepare))
        times["side by side"].append(timed(side_by_side))
    for name, ts in times.items():
        print(f"{name:<32} {statistics.median(ts):9.2f} {min(ts):7.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--rev", default="HEAD", help="the git revision of the old way")
    parser.add_argument("--no-outputs", action="store_true", help="only the EXR rows")
    parser.add_argument("--exr-threads", type=int, default=None, help="an extra row")
    parser.add_argument("--surface", default="smooth")
    parser.add_argument(
        "--overlap-probe", action="store_true", help="only the picture against the paint channels"
    )
    args = parser.parse_args()
    if args.overlap_probe:
        overlap_probe(painted_canvas(args.surface), args.rounds)
        return

    with tempfile.TemporaryDirectory(prefix="bench_outputs_") as folder:
        tmp = Path(folder)
        old_exr = committed_module(args.rev, "paintapp/canvas/exr.py", "old_exr", tmp)
        old_outputs = committed_module(args.rev, "paintapp/session/outputs.py", "old_outputs", tmp)
        vars(old_outputs)["write_canvas_exr"] = old_exr.write_canvas_exr  # the old EXR inside
        canvas = painted_canvas(args.surface)
        rgba = picture(canvas)

        cases: dict[str, Callable[[], None]] = {
            "exr old": lambda: old_exr.write_canvas_exr(tmp / "old.exr", canvas, rgba),
            "exr new": lambda: new_exr.write_canvas_exr(tmp / "new.exr", canvas, rgba),
        }
        if args.exr_threads is not None:
            cases[f"exr new, {args.exr_threads} OpenEXR threads"] = lambda: patched(
                new_exr,
                "EXR_THREADS",
                args.exr_threads,
                lambda: new_exr.write_canvas_exr(tmp / "threads.exr", canvas, rgba),
            )
        if not args.no_outputs:
            cases["outputs old"] = lambda: old_outputs.write_canvas_outputs(
                canvas, tmp / "old_out.exr", tmp / "old_out.png"
            )
            cases["outputs new"] = lambda: new_outputs.write_canvas_outputs(
                canvas, tmp / "new_out.exr", tmp / "new_out.png"
            )

        times: dict[str, list[float]] = {name: [] for name in cases}
        for r in range(args.rounds):
            for name, fn in cases.items():
                times[name].append(timed(fn))
            print(f"round {r + 1}: " + ", ".join(f"{n} {t[-1]:.2f}" for n, t in times.items()))

        old, new = (
            new_exr.stored_channels(tmp / "old.exr")[1],
            new_exr.stored_channels(tmp / "new.exr")[1],
        )
        assert list(old) == list(new), (list(old), list(new))
        for name in old:
            assert old[name].dtype == new[name].dtype, name
            assert np.array_equal(old[name].view(np.uint8), new[name].view(np.uint8)), name
        print(f"old and new EXR: {len(old)} channels, equal bit for bit")

        print(f"\n{'case':<32} {'median s':>9} {'min s':>7} {'file MB':>8}")
        files = {
            "exr old": "old.exr",
            "exr new": "new.exr",
            "outputs old": "old_out.exr",
            "outputs new": "new_out.exr",
        }
        for name, ts in times.items():
            extra = {"rows": "rows.exr", "threads": "threads.exr"}
            file = tmp / files.get(name, next((f for k, f in extra.items() if k in name), ""))
            size = file.stat().st_size / 1e6 if file.exists() else float("nan")
            print(f"{name:<32} {statistics.median(ts):9.2f} {min(ts):7.2f} {size:8.2f}")


if __name__ == "__main__":
    main()
