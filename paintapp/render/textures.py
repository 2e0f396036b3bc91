"""The canvas on the GPU: pigment concentrations and the paint surface as textures.

- ``concentration``: a 2D texture array, RGBA half floats; layer ``l`` channel ``j`` holds the
  volume fraction of pigment ``4 l + j``. Half precision (11 bits) is ample for a colour fraction
  and halves the memory of a 4096x4096 canvas (128 MiB per 4 pigments).
- ``surface``: RG 32-bit floats, r = paint height (metres; needs full precision for the relief),
  g = wetness.

Texture row 0 is canvas row 0 (the bottom), matching GL's texture coordinates. Uploads cover only
a texel box (the canvas's dirty region), processed in strips so a full 4096x4096 upload never
builds more than a few tens of MiB of temporaries. A large box (a new canvas, a rebuild) is first
zeroed, which is what bare canvas uploads as, and only the part of it holding paint or wetness
is computed and sent: a blank A4 canvas at 0.1 mm (6.2 million texels) uploads in milliseconds.
"""

from __future__ import annotations

import moderngl
import numpy as np

from paintapp.canvas.half_floats import half_bits
from paintapp.canvas.model import Canvas
from paintapp.canvas.regions import Box, box_of_nonzero
from solver import inline_kernel, kernel

#: Texels per upload strip (bounds temporary memory).
STRIP_TEXELS = 1 << 21
#: Boxes of at least this many texels are zeroed and only their painted part computed.
ZERO_FILL_TEXELS = 1 << 20


def layer_count(pigment_count: int) -> int:
    """Concentration layers needed for ``pigment_count`` pigments (at least 1)."""
    return max(1, -(-pigment_count // 4))


class CanvasTextures:
    """GPU textures mirroring one canvas size and pigment count, at full resolution or averaged
    over ``reduction`` x ``reduction`` texel blocks (a coarser copy to draw minified views from:
    a fraction of the upload work, and no aliasing of detail finer than a pixel)."""

    def __init__(
        self,
        ctx: moderngl.Context,
        pixels: tuple[int, int],
        pigment_count: int,
        reduction: int = 1,
    ) -> None:
        if reduction < 1:
            raise ValueError(f"the reduction must be a positive integer, got {reduction}")
        self.canvas_pixels = (int(pixels[0]), int(pixels[1]))
        self.reduction = int(reduction)
        w, h = (-(-n // self.reduction) for n in self.canvas_pixels)
        self.pixels = (w, h)
        self.pigment_count = pigment_count
        self.layers = layer_count(pigment_count)
        self.concentration = ctx.texture_array((w, h, self.layers), 4, dtype="f2")
        self.surface = ctx.texture((w, h), 2, dtype="f4")
        # what the surface texture holds, so that drying re-sends the wetness alone
        self.surface_cpu = np.zeros((h, w, 2), np.float32)
        for texture in (self.concentration, self.surface):
            texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
            texture.repeat_x = False
            texture.repeat_y = False

    def fits(self, canvas: Canvas, reduction: int = 1) -> bool:
        """Whether these textures can hold ``canvas`` (same size, enough layers) reduced so."""
        return (
            self.canvas_pixels == canvas.pixels
            and self.reduction == reduction
            and layer_count(len(canvas.pigment_names)) == self.layers
        )

    def coarse(self, box: Box) -> Box:
        """The texture texels holding canvas texel box ``box``."""
        f = self.reduction
        x0, y0, x1, y1 = box
        return x0 // f, y0 // f, -(-x1 // f), -(-y1 // f)

    def upload(self, canvas: Canvas, box: Box) -> None:
        """Copy the texels of ``box`` (x0, y0, x1, y1, canvas texels) from the canvas to the GPU."""
        target = self.coarse(box)
        x0, y0, x1, y1 = target
        if (x1 - x0) * (y1 - y0) >= ZERO_FILL_TEXELS:
            self._zero(target)
            content = content_box(canvas, box)
            if content is None:
                return
            x0, y0, x1, y1 = self.coarse(content)
        rows = max(1, STRIP_TEXELS // max(1, x1 - x0))
        for r0 in range(y0, y1, rows):
            self._upload_strip(canvas, (x0, r0, x1, min(y1, r0 + rows)))

    def upload_wetness(self, canvas: Canvas, box: Box) -> None:
        """Re-send the wetness of canvas texel box ``box``, whose paint did not change (drying):
        one float per canvas texel read, instead of every pigment's paint."""
        x0, y0, x1, y1 = self.coarse(box)
        region = self.surface_cpu[y0:y1, x0:x1]
        block_means(canvas.wetness, self.reduction, x0, y0, region[..., 1])
        self.surface.write(np.ascontiguousarray(region), viewport=(x0, y0, x1 - x0, y1 - y0))

    def _zero(self, box: Box) -> None:
        """Write bare canvas (all zero) over ``box``, in strips."""
        x0, y0, x1, y1 = box
        w = x1 - x0
        rows = max(1, STRIP_TEXELS // max(1, w))
        for r0 in range(y0, y1, rows):
            h = min(y1, r0 + rows) - r0
            conc = np.zeros((self.layers, h, w, 4), np.float16)
            self.concentration.write(conc, viewport=(x0, r0, 0, w, h, self.layers))
            self.surface.write(np.zeros((h, w, 2), np.float32), viewport=(x0, r0, w, h))
            self.surface_cpu[r0 : r0 + h, x0:x1] = 0.0

    def _upload_strip(self, canvas: Canvas, box: Box) -> None:
        """Upload texture texels ``box`` (their averages over the canvas's texels)."""
        x0, y0, x1, y1 = box
        w, h = x1 - x0, y1 - y0
        conc = np.empty((self.layers, h, w, 4), np.float32)
        surface = np.empty((h, w, 2), np.float32)
        pack_region(canvas.paint_m, self.reduction, x0, y0, conc, surface[..., 0])
        block_means(canvas.wetness, self.reduction, x0, y0, surface[..., 1])
        halves = np.empty(conc.shape, np.uint16)  # the half floats' bits
        half_bits(conc.reshape(-1).view(np.uint32), halves.reshape(-1))
        self.concentration.write(halves, viewport=(x0, y0, 0, w, h, self.layers))
        self.surface.write(surface, viewport=(x0, y0, w, h))
        self.surface_cpu[y0:y1, x0:x1] = surface

    def release(self) -> None:
        self.concentration.release()
        self.surface.release()


@kernel
def pack_region(
    paint: np.ndarray,
    reduction: int,
    x0: int,
    y0: int,
    conc: np.ndarray,
    height: np.ndarray,
) -> None:
    """One pass over the texture texels of a box from (``x0``, ``y0``): ``conc`` (layers, h, w,
    4) gets each pigment's volume fraction (``paint / total`` in float32, 0 where there is no
    paint; channels past the pigments 0), ``height`` (h, w) the paint height (the float32 sum
    over the pigments). With ``reduction`` 1 a texture texel is a canvas texel: the same values
    as :meth:`Canvas.concentration_region` and ``paint.sum(axis=0, dtype=float32)``, without
    their temporaries. With ``reduction`` f each pigment's paint is first averaged over an f x f
    block of canvas texels as :func:`block_means` does (fewer texels at the canvas's far edges),
    and the fractions and height are taken from those means."""
    pigments = paint.shape[0]
    channels = conc.shape[0] * 4
    rows, cols = paint.shape[1], paint.shape[2]
    zero = np.float32(0.0)
    means = np.zeros(max(pigments, 1), np.float32)
    for y in range(conc.shape[1]):
        for x in range(conc.shape[2]):
            for p in range(pigments):
                if reduction == 1:  # no slice per texel on the full-resolution path
                    means[p] = paint[p, y0 + y, x0 + x]
                else:
                    means[p] = _block_mean(paint[p], reduction, x0 + x, y0 + y, rows, cols)
            total = zero
            for p in range(pigments):
                total += means[p]
            height[y, x] = total
            for q in range(channels):
                value = zero
                if q < pigments and total > zero:
                    value = means[q] / total
                conc[q // 4, y, x, q % 4] = value


@inline_kernel
def _block_mean(values: np.ndarray, reduction: int, bx: int, by: int, rows: int, cols: int):
    """The mean of block (``bx``, ``by``) of ``values`` (float64 sum, float32 result); the
    value itself for ``reduction`` 1."""
    if reduction == 1:
        return values[by, bx]
    ty0, tx0 = by * reduction, bx * reduction
    ty1, tx1 = min(ty0 + reduction, rows), min(tx0 + reduction, cols)
    acc = 0.0
    for ty in range(ty0, ty1):
        for tx in range(tx0, tx1):
            acc += values[ty, tx]
    return np.float32(acc / max((ty1 - ty0) * (tx1 - tx0), 1))


@kernel
def block_means(values: np.ndarray, reduction: int, x0: int, y0: int, out: np.ndarray) -> None:
    """``out`` (h, w) gets the means of ``values``'s ``reduction`` x ``reduction`` blocks from
    block (``x0``, ``y0``) on (fewer texels at the far edges; the values themselves for 1)."""
    rows, cols = values.shape
    for y in range(out.shape[0]):
        for x in range(out.shape[1]):
            out[y, x] = _block_mean(values, reduction, x0 + x, y0 + y, rows, cols)


def content_box(canvas: Canvas, box: Box) -> Box | None:
    """The part of ``box`` holding any paint or wetness (canvas coordinates), or None."""
    x0, y0, x1, y1 = box
    mask = canvas.wetness[y0:y1, x0:x1] != 0.0
    for p in range(len(canvas.pigment_names)):
        mask |= canvas.paint_m[p, y0:y1, x0:x1] != 0.0
    inner = box_of_nonzero(mask)
    if inner is None:
        return None
    return (x0 + inner[0], y0 + inner[1], x0 + inner[2], y0 + inner[3])
