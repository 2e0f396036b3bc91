"""Time the sweep's reading pass as an OpenGL compute shader beside its numba kernel.

The write-back's largest pass, the sweep (:func:`paintapp.paint.columns_kernels.sweep_change`),
reads the step's change and lost fraction at a few points along the tip's path behind every
texel of its box (:func:`paintapp.paint.columns_kernels._swept_fields`): the one per-texel pass
of the write-back with no sums or flood fills in it, so the one a compute shader on the canvas's
textures could take whole. This benchmark runs that pass both ways on the same fields, the
window's case (the box and travel of ``round_large`` on 0.1 mm texels, ``--box`` and
``--travel`` to change them), checks that they agree, and prints median milliseconds of:

- the numba kernel (one thread, as the window paints);
- the shader with the fields resident on the device (the dispatch and its wait only: what the
  pass would cost if the paint lived in textures);
- the shader with the fields uploaded before and the three results read back after (what it
  costs while the paint lives in numpy arrays).

On a machine without a GPU the shader runs on Mesa's llvmpipe (the renderer's name is printed).

    python benchmarks/bench_texel_shader.py [--repeats N] [--box NY NX] [--travel DX DY]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time

import numpy as np

from paintapp.paint.columns_kernels import _swept_fields, sweep_reads

#: The window row's box (texels, rows x columns) and its step's travel (texels, x and y).
WINDOW_BOX = (183, 313)
WINDOW_TRAVEL = (10.4, 1.2)
#: A sample every this many texels (the window's brush: nine texels a cell, three a cell).
SPACING_TEXELS = 3.0
LOCAL = 16

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
uniform ivec2 offs[8];
uniform vec4 w[8];
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


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=200)
    parser.add_argument("--box", type=int, nargs=2, default=WINDOW_BOX, metavar=("NY", "NX"))
    parser.add_argument("--travel", type=float, nargs=2, default=WINDOW_TRAVEL,
                        metavar=("DX", "DY"))  # fmt: skip
    args = parser.parse_args(argv)
    if args.repeats < 1 or min(args.box) < 1:
        parser.error("--repeats and the box's sides must be at least 1")
    dx, dy = args.travel
    samples, pad_x, pad_y = sweep_reads(dx, dy, SPACING_TEXELS)
    if samples == 0:
        parser.error("--travel under half a texel is not swept")
    ny, nx = args.box
    change, frac = fields((ny, nx), (pad_x, pad_y))
    outputs = [np.empty((ny, nx), np.float32) for _ in range(3)]
    path = (pad_x, pad_y, dx, dy, samples)

    def numba_pass() -> None:
        _swept_fields((change, frac), path, *outputs)

    cpu_ms = median_ms(numba_pass, args.repeats)

    try:
        import moderngl

        ctx = moderngl.create_standalone_context(backend="egl", require=430)
    except Exception as exc:  # no EGL, or no GL 4.3 for compute shaders
        print(f"numba: {cpu_ms:.3f} ms; no compute shaders here: {exc}", file=sys.stderr)
        return 1
    program = ctx.compute_shader(SHADER.replace("LOCAL", str(LOCAL)))
    offs, weights = path_samples(dx, dy, samples)
    program["size"].value = (nx, ny)
    program["pad"].value = (pad_x, pad_y)
    program["stride"].value = change.shape[1]
    program["samples"].value = samples
    program["offs"].write(np.resize(offs, (8, 2)).astype(np.int32).tobytes())
    program["w"].write(np.resize(weights, (8, 4)).astype(np.float32).tobytes())
    inputs = [ctx.buffer(change.tobytes()), ctx.buffer(frac.tobytes())]
    results = [ctx.buffer(reserve=4 * nx * ny) for _ in range(3)]
    for binding, buffer in enumerate(inputs + results):
        buffer.bind_to_storage_buffer(binding)
    groups = (-(-nx // LOCAL), -(-ny // LOCAL))

    def resident() -> None:
        program.run(*groups)
        ctx.finish()

    def round_trip() -> None:
        inputs[0].write(change.tobytes())
        inputs[1].write(frac.tobytes())
        program.run(*groups)
        for buffer, out in zip(results, outputs, strict=True):
            buffer.read_into(out)

    numba_pass()
    expected = [o.copy() for o in outputs]
    round_trip()
    worst = max(
        float(np.max(np.abs(o - e)) / max(float(np.max(np.abs(e))), 1e-30))
        for o, e in zip(outputs, expected, strict=True)
    )
    resident_ms = median_ms(resident, args.repeats)
    trip_ms = median_ms(round_trip, args.repeats)
    print(f"the sweep's reading pass, {ny} x {nx} texels, {samples} samples along "
          f"({dx:g}, {dy:g}) texels; shader on {ctx.info['GL_RENDERER']}")  # fmt: skip
    print("| numba, one thread | shader, fields resident | shader, upload and read back |")
    print("|---|---|---|")
    print(f"| {cpu_ms:.3f} ms | {resident_ms:.3f} ms | {trip_ms:.3f} ms |")
    print(f"largest difference between the two, over the largest value: {worst:.2g}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
