"""Time the sweep's reading pass as an OpenGL compute shader beside its numba kernel.

The write-back's largest pass, the sweep (:func:`paintapp.paint.columns_kernels.sweep_change`),
reads the step's change and lost fraction at a few points along the tip's path behind every
texel of its box (:func:`paintapp.paint.columns_kernels._swept_fields`): the one per-texel pass
of the write-back with no sums or flood fills in it, so the one a compute shader on the canvas's
textures could take whole. This benchmark runs that pass both ways on the same fields, the
window's case (the box and travel of ``round_large`` on 0.1 mm texels, ``--box`` and
``--travel`` to change them), checks that they agree, and prints median milliseconds of:

- the numba kernel (one thread, as the window paints);
- the shader, in two forms (the fields in storage buffers, or in float textures read with
  ``texelFetch`` and the results written as images), with the fields resident on the device
  (the dispatch and its wait only: what the pass would cost if the paint lived there), and with
  the fields uploaded before and the three results read back after (what it costs while the
  paint lives in numpy arrays).

On a machine without a GPU the shader runs on Mesa's llvmpipe (the renderer's name is printed).

    python benchmarks/bench_texel_shader.py [--repeats N] [--box NY NX] [--travel DX DY]
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from paintapp.paint.columns_kernels import _swept_fields, sweep_reads

#: The window row's box (texels, rows x columns) and its step's travel (texels, x and y).
WINDOW_BOX = (183, 313)
WINDOW_TRAVEL = (10.4, 1.2)
#: A sample every this many texels (the window's brush: nine texels a cell, three a cell).
SPACING_TEXELS = 3.0
LOCAL = 16
#: The largest box side and travel the benchmark takes (texels).
MAX_BOX = 4096
#: The most samples along the path the shaders take (their uniform arrays' length).
READS = 64

SHADER = """
#version 430
layout(local_size_x = LOCAL, local_size_y = LOCAL) in;
layout(std430, binding = 0) readonly buffer Change { float change[]; };
layout(std430, binding = 1) readonly buffer Frac { float frac[]; };
layout(std430, binding = 2) writeonly buffer Gain { float gain_s[]; };
layout(std430, binding = 3) writeonly buffer Loss { float loss_s[]; };
layout(std430, binding = 4) writeonly buffer Cap { float cap[]; };
uniform ivec2 size;
uniform ivec2 pad;
uniform int stride;
uniform int samples;
uniform ivec2 offs[READS];
uniform vec4 w[READS];
void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= size.x || p.y >= size.y) return;
    float g = 0.0, l = 0.0, c = 0.0;
    for (int k = 0; k < samples; ++k) {
        int a = (p.y + pad.y + offs[k].y) * stride + p.x + pad.x + offs[k].x;
        int b = a + stride;
        vec4 cv = vec4(change[a], change[a + 1], change[b], change[b + 1]);
        vec4 fv = vec4(frac[a], frac[a + 1], frac[b], frac[b + 1]);
        g += dot(w[k], max(cv, 0.0));
        l += dot(w[k], max(-cv, 0.0));
        c = max(c, dot(w[k], fv));
    }
    int o = p.y * size.x + p.x;
    float mean = 1.0 / float(samples);
    gain_s[o] = g * mean;
    loss_s[o] = l * mean;
    cap[o] = c;
}
"""


TEXTURE_SHADER = """
#version 430
layout(local_size_x = LOCAL, local_size_y = LOCAL) in;
layout(binding = 0) uniform sampler2D change;
layout(binding = 1) uniform sampler2D frac;
layout(r32f, binding = 0) writeonly uniform image2D gain_s;
layout(r32f, binding = 1) writeonly uniform image2D loss_s;
layout(r32f, binding = 2) writeonly uniform image2D cap;
uniform ivec2 size;
uniform ivec2 pad;
uniform int samples;
uniform ivec2 offs[READS];
uniform vec4 w[READS];
vec4 quad(sampler2D field, ivec2 a) {
    return vec4(texelFetch(field, a, 0).r, texelFetch(field, a + ivec2(1, 0), 0).r,
                texelFetch(field, a + ivec2(0, 1), 0).r, texelFetch(field, a + ivec2(1, 1), 0).r);
}
void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= size.x || p.y >= size.y) return;
    float g = 0.0, l = 0.0, c = 0.0;
    for (int k = 0; k < samples; ++k) {
        ivec2 a = p + pad + offs[k];
        vec4 cv = quad(change, a);
        g += dot(w[k], max(cv, 0.0));
        l += dot(w[k], max(-cv, 0.0));
        c = max(c, dot(w[k], quad(frac, a)));
    }
    float mean = 1.0 / float(samples);
    imageStore(gain_s, p, vec4(g * mean));
    imageStore(loss_s, p, vec4(l * mean));
    imageStore(cap, p, vec4(c));
}
"""


def sized(source: str) -> str:
    """A shader's source with its work group's side and its arrays' length filled in."""
    return source.replace("LOCAL", str(LOCAL)).replace("READS", str(READS))


def fields(box: tuple[int, int], pad: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """The change (a loss under a brush-shaped blob, a gain at its front) and the fraction lost,
    float32, padded with ``pad`` (x, y) zeros on every side, as the sweep pads them."""
    ny, nx = box
    y, x = np.mgrid[0:ny, 0:nx]
    r2 = ((x - 0.5 * nx) / (0.3 * nx)) ** 2 + ((y - 0.5 * ny) / (0.4 * ny)) ** 2
    front = np.exp(-(((x - 0.75 * nx) / (0.05 * nx)) ** 2)) * (r2 < 1.0)
    change = np.where(r2 < 1.0, -2e-5 * (1.0 - r2) + 6e-5 * front, 0.0)
    frac = np.clip(-change / 1e-4, 0.0, 1.0)
    out = []
    for f in (change, frac):
        padded = np.zeros((ny + 2 * pad[1], nx + 2 * pad[0]), np.float32)
        padded[pad[1] : pad[1] + ny, pad[0] : pad[0] + nx] = f
        out.append(padded)
    return out[0], out[1]


def path_samples(dx: float, dy: float, samples: int) -> tuple[np.ndarray, np.ndarray]:
    """Each sample's whole-texel offsets (samples, 2) and bilinear weights (samples, 4), as
    :func:`paintapp.paint.columns_kernels._path_samples` forms them."""
    s = (np.arange(samples) + 0.5) / samples
    ox, oy = s * dx, s * dy
    i0, j0 = np.floor(ox), np.floor(oy)
    fx, fy = ox - i0, oy - j0
    w = np.stack([(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy], axis=1)
    return np.stack([i0, j0], axis=1).astype(np.int32), w.astype(np.float32)


def median_ms(run, repeats: int) -> float:
    """Median wall milliseconds of ``run()`` over ``repeats`` calls after one warm-up."""
    run()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        times.append(1e3 * (time.perf_counter() - start))
    return statistics.median(times)


@dataclass(frozen=True)
class Case:
    """The pass's inputs: the padded fields, the box (ny, nx), the padding (x, y), the travel
    (dx, dy) and the number of samples along it."""

    change: np.ndarray
    frac: np.ndarray
    box: tuple[int, int]
    pad: tuple[int, int]
    travel: tuple[float, float]
    samples: int


def set_uniforms(program, case: Case) -> None:
    """The box, padding and path samples both shader forms read."""
    offs, weights = path_samples(*case.travel, case.samples)
    program["size"].value = (case.box[1], case.box[0])
    program["pad"].value = case.pad
    program["samples"].value = case.samples
    program["offs"].write(np.resize(offs, (READS, 2)).astype(np.int32).tobytes())
    program["w"].write(np.resize(weights, (READS, 4)).astype(np.float32).tobytes())


def with_transfers(case: Case, objects: tuple[list, list], resident: Callable,
                   outputs: list[np.ndarray]) -> Callable:  # fmt: skip
    """``resident`` with the fields uploaded to ``objects``' inputs (buffers or textures) before
    and its results read into ``outputs`` after."""
    inputs, results = objects

    def round_trip() -> None:
        for field, target in zip((case.change, case.frac), inputs, strict=True):
            target.write(field.tobytes())
        resident()
        for source, out in zip(results, outputs, strict=True):
            source.read_into(out)

    return round_trip


def buffer_form(ctx, case: Case, outputs: list[np.ndarray]) -> tuple[Callable, Callable]:
    """(resident, round trip) runs of the shader on storage buffers; the round trip writes
    ``outputs``."""
    ny, nx = case.box
    program = ctx.compute_shader(sized(SHADER))
    set_uniforms(program, case)
    program["stride"].value = case.change.shape[1]
    inputs = [ctx.buffer(case.change.tobytes()), ctx.buffer(case.frac.tobytes())]
    results = [ctx.buffer(reserve=4 * nx * ny) for _ in range(3)]
    groups = (-(-nx // LOCAL), -(-ny // LOCAL))

    def resident() -> None:
        for binding, buffer in enumerate(inputs + results):
            buffer.bind_to_storage_buffer(binding)
        program.run(*groups)
        ctx.finish()

    return resident, with_transfers(case, (inputs, results), resident, outputs)


def texture_form(ctx, case: Case, outputs: list[np.ndarray]) -> tuple[Callable, Callable]:
    """(resident, round trip) runs of the shader on float textures (read by ``texelFetch``,
    written as images); the round trip writes ``outputs``."""
    import moderngl

    ny, nx = case.box
    program = ctx.compute_shader(sized(TEXTURE_SHADER))
    set_uniforms(program, case)
    size = (case.change.shape[1], case.change.shape[0])
    inputs = [ctx.texture(size, 1, f.tobytes(), dtype="f4") for f in (case.change, case.frac)]
    for texture in inputs:
        texture.filter = (moderngl.NEAREST, moderngl.NEAREST)
    results = [ctx.texture((nx, ny), 1, dtype="f4") for _ in range(3)]
    groups = (-(-nx // LOCAL), -(-ny // LOCAL))

    def resident() -> None:
        for unit, texture in enumerate(inputs):
            texture.use(unit)
        for unit, texture in enumerate(results):
            texture.bind_to_image(unit, read=False, write=True)
        program.run(*groups)
        ctx.finish()

    return resident, with_transfers(case, (inputs, results), resident, outputs)


def largest_difference(outputs: list[np.ndarray], expected: list[np.ndarray]) -> float:
    """The largest difference between two sets of results, over the largest expected value."""
    return max(
        float(np.max(np.abs(o - e)) / max(float(np.max(np.abs(e))), 1e-30))
        for o, e in zip(outputs, expected, strict=True)
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=200)
    parser.add_argument("--box", type=int, nargs=2, default=WINDOW_BOX, metavar=("NY", "NX"))
    parser.add_argument("--travel", type=float, nargs=2, default=WINDOW_TRAVEL,
                        metavar=("DX", "DY"))  # fmt: skip
    args = parser.parse_args(argv)
    if args.repeats < 1 or not 1 <= min(args.box) <= max(args.box) <= MAX_BOX:
        parser.error(f"--repeats must be at least 1, the box's sides 1 to {MAX_BOX} texels")
    if not all(math.isfinite(d) and abs(d) <= MAX_BOX for d in args.travel):
        parser.error(f"--travel takes finite texels, at most {MAX_BOX} each way")
    samples, pad_x, pad_y = sweep_reads(*args.travel, SPACING_TEXELS)
    if samples == 0:
        parser.error("--travel under half a texel is not swept")
    if samples > READS:
        parser.error(f"--travel takes {samples} samples; the shaders take at most {READS}")
    box = (args.box[0], args.box[1])
    change, frac = fields(box, (pad_x, pad_y))
    case = Case(change, frac, box, (pad_x, pad_y), tuple(args.travel), samples)
    expected = [np.empty(box, np.float32) for _ in range(3)]
    path = (pad_x, pad_y, *case.travel, samples)
    cpu_ms = median_ms(lambda: _swept_fields((change, frac), path, *expected), args.repeats)
    try:
        import moderngl

        ctx = moderngl.create_standalone_context(backend="egl", require=430)
    except Exception as exc:  # no EGL, or no GL 4.3 for compute shaders
        print(f"numba: {cpu_ms:.3f} ms; no compute shaders here: {exc}", file=sys.stderr)
        return 1
    print(f"the sweep's reading pass, {box[0]} x {box[1]} texels, {samples} samples along "
          f"({case.travel[0]:g}, {case.travel[1]:g}) texels; numba on one thread: "
          f"{cpu_ms:.3f} ms; shaders on {ctx.info['GL_RENDERER']}")  # fmt: skip
    print("| shader form | fields resident | upload and read back | largest difference |")
    print("|---|---|---|---|")
    for name, form in (("storage buffers", buffer_form), ("textures", texture_form)):
        outputs = [np.empty(box, np.float32) for _ in range(3)]
        resident, round_trip = form(ctx, case, outputs)
        round_trip()
        worst = largest_difference(outputs, expected)
        resident_ms = median_ms(resident, args.repeats)
        trip_ms = median_ms(round_trip, args.repeats)
        print(f"| {name} | {resident_ms:.3f} ms | {trip_ms:.3f} ms | {worst:.2g} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
