"""The canvas renderer: Kubelka-Munk paint colour, impasto lighting and overlays with moderngl.

Typical use (the painting loop)::

    renderer = CanvasRenderer(ctx, library)
    renderer.update(canvas)                 # uploads only the canvas's dirty region
    renderer.render(size=(w, h), view=view, outlines=[...], arrows=[...], framebuffer=fbo)

and headless export::

    rgba = renderer.render_linear_rgba(canvas)   # (H, W, 4) float32, row 0 = canvas bottom

:meth:`CanvasRenderer.render_cached` mixes and lights each canvas texel once into a cached
picture (again only where the canvas changed, everywhere when the pigments, lighting or canvas
size change, and only as far as the view shows: the rest waits until it is in sight) and samples
it, each texel drawn sharp: cheaper than :meth:`CanvasRenderer.render` wherever a texel covers
more than one output pixel. Both draw through a view: an upright :class:`ViewRect` (exports) or
the window's zoomed, panned and turned :class:`CanvasView`, and only inside the context's scissor
box. Output is linear
scene-referred RGB with sRGB/Rec.709 primaries under D65 (see :mod:`paintapp.pigments.spectra`);
alpha is 1 on the canvas.
"""

from __future__ import annotations

from collections.abc import Sequence

import moderngl
import numpy as np

from paintapp.canvas.model import MAX_PIGMENTS, Canvas
from paintapp.canvas.regions import Box, clip_box, union_box
from paintapp.canvas.surfaces import block_mean, relief_m
from paintapp.pigments.bands import Bands, BandTable, band_table
from paintapp.pigments.library import PigmentLibrary
from paintapp.render.context import load_program
from paintapp.render.overlays import BrushOutline, ForceArrow, arrow_triangles, outline_triangles
from paintapp.render.sight import split_stale, texel_box_in_sight
from paintapp.render.textures import CanvasTextures
from paintapp.render.view import Lighting, ViewRect
from paintapp.render.view_transform import CanvasView

#: What the renderer draws through: an upright canvas rectangle (exports) or the painting
#: window's zoomed, panned and turned view.
View = ViewRect | CanvasView

#: Colour outside the canvas, linear RGBA.
BACKGROUND = (0.02, 0.02, 0.02, 1.0)


class CanvasRenderer:
    """Draws one canvas at a time into an offscreen float target or a given framebuffer.

    Args:
        ctx: an OpenGL 3.3+ context (see :func:`paintapp.render.context.create_headless_context`).
        library: where the canvas's pigments come from.
        bands: spectral bands of the mixing (must be a multiple of 4 bands).
        lighting: the initial light; change it with the ``lighting`` attribute.
    """

    def __init__(
        self,
        ctx: moderngl.Context,
        library: PigmentLibrary,
        bands: Bands | None = None,
        lighting: Lighting | None = None,
    ) -> None:
        self.ctx = ctx
        self.library = library
        self.bands = bands or Bands()
        if self.bands.count % 4:
            raise ValueError(f"the shader needs a multiple of 4 bands, got {self.bands.count}")
        self.lighting = lighting or Lighting()
        #: Draw from textures averaged over ``reduction`` x ``reduction`` canvas texels (a view
        #: that shows several texels per pixel needs no more); 1 draws every texel. A change
        #: rebuilds the textures at the next :meth:`update`.
        self.reduction = 1
        self.table: BandTable | None = None
        self._textures: CanvasTextures | None = None
        self._canvas_size_m = (1.0, 1.0)
        self._texel_m = (1.0, 1.0)
        self._target: moderngl.Framebuffer | None = None
        self._programs: dict[int, moderngl.Program] = {}
        self._overlay = load_program(ctx, "overlay")
        quad = np.zeros((4, 2), np.float32)
        self._quad = ctx.buffer(quad.tobytes())
        self._quad_vaos: dict[int, moderngl.VertexArray] = {}
        self._picture_program = load_program(ctx, "picture")
        self._picture_vao = ctx.vertex_array(
            self._picture_program, [(self._quad, "2f", "in_pos_m")]
        )
        self._picture: moderngl.Texture | None = None
        self._picture_fbo: moderngl.Framebuffer | None = None
        self._picture_lighting: Lighting | None = None
        self._stale: list[Box] = []  # texel boxes whose cached colour is out of date
        # the canvas surface's tooth heights, on the textures' texels (a 1 x 1 zero when smooth)
        self._tooth: moderngl.Texture | None = None
        self._tooth_key: tuple | None = None
        self._tooth_relief_m = 0.0

    # --- canvas upload ------------------------------------------------------------------------
    def _canvas_program(self, layers: int) -> moderngl.Program:
        if layers not in self._programs:
            defines = {"N_GROUPS": self.bands.count // 4, "MAX_PIGMENTS": MAX_PIGMENTS}
            self._programs[layers] = load_program(
                self.ctx, "canvas", {**defines, "N_LAYERS": layers}
            )
        return self._programs[layers]

    def update(self, canvas: Canvas) -> Box | None:
        """Bring the GPU copy up to date with ``canvas``; returns the canvas texel box uploaded.

        Only the canvas's dirty region is sent (``canvas.take_dirty()``), and only the wetness
        where nothing else changed (``canvas.take_wet_dirty()``: drying). A new pigment appended
        to the canvas costs nothing more while it fits the existing texture layers (its channel
        is zero everywhere); a new canvas size, a reordered pigment list or a fifth (ninth, ...)
        pigment rebuilds the textures and uploads everything.
        """
        names = canvas.pigment_names
        if self.table is None or self.table.names != names:
            appended = self.table is not None and names[: len(self.table.names)] == self.table.names
            self.table = band_table(self.library.require(names), self.bands)
            if not appended:
                canvas.mark_all_dirty()
        textures = self._textures
        if textures is None or not textures.fits(canvas, self.reduction):
            if textures is not None:
                textures.release()
            textures = CanvasTextures(self.ctx, canvas.pixels, len(names), self.reduction)
            self._textures = textures
            canvas.mark_all_dirty()
        textures.pigment_count = len(names)
        self._canvas_size_m = canvas.size_m
        # the textures' own texel (the lighting's slopes are taken over it)
        (w_m, h_m), (w, h) = canvas.size_m, textures.pixels
        self._texel_m = (w_m / w, h_m / h)
        box = canvas.take_dirty()
        if box is not None:
            textures.upload(canvas, box)
        wet = canvas.take_wet_dirty()
        if wet is not None:
            textures.upload_wetness(canvas, wet)
        self._update_tooth(canvas, textures)
        changed = union_box(box, wet)
        if changed is not None:
            # the lighting reads the height one texel either side
            x0, y0, x1, y1 = textures.coarse(changed)
            grown = clip_box((x0 - 1, y0 - 1, x1 + 1, y1 + 1), textures.pixels)
            if grown is not None:
                self._stale.append(grown)
        return changed

    def _update_tooth(self, canvas: Canvas, textures: CanvasTextures) -> None:
        """Upload the canvas surface's tooth (block means over the textures' reduction) when the
        surface, the size or the reduction changed; the whole cached picture goes stale."""
        key = (canvas.surface, canvas.pixels, canvas.size_m, textures.pixels, textures.reduction)
        if key == self._tooth_key and self._tooth is not None:
            return
        if self._tooth is not None:
            self._tooth.release()
        if canvas.has_tooth:
            tooth = block_mean(canvas.tooth_m, textures.reduction, textures.pixels)
            self._tooth_relief_m = relief_m(canvas.surface)
        else:
            tooth = np.zeros((1, 1), np.float32)
            self._tooth_relief_m = 0.0
        h, w = tooth.shape
        self._tooth = self.ctx.texture((w, h), 1, tooth.tobytes(), dtype="f4")
        self._tooth.filter = (moderngl.LINEAR, moderngl.LINEAR)
        self._tooth.repeat_x = self._tooth.repeat_y = False
        self._tooth_key = key
        self._stale.append((0, 0, *textures.pixels))

    def _set_uniforms(self, program: moderngl.Program, view: View) -> None:
        table = self.table
        assert table is not None
        p = len(table.names)
        k = np.zeros((MAX_PIGMENTS, self.bands.count), np.float32)
        s = np.zeros_like(k)
        k[:p], s[:p] = table.k_per_m, table.s_per_m
        _uniform(program, "u_view").write(view.matrix().T.copy().tobytes())
        _uniform(program, "u_concentration").value = 0
        _uniform(program, "u_surface").value = 1
        _uniform(program, "u_tooth").value = 2
        _uniform(program, "u_tooth_relief_m").value = self._tooth_relief_m
        if self._tooth is not None:
            self._tooth.use(2)
        _uniform(program, "u_canvas_size_m").value = self._canvas_size_m
        _uniform(program, "u_texel_m").value = self._texel_m
        _uniform(program, "u_pigment_count").value = p
        _write_vec4_array(program, "u_k", k)
        _write_vec4_array(program, "u_s", s)
        _write_vec4_array(program, "u_ground", table.ground)
        for i, channel in enumerate("rgb"):
            _write_vec4_array(program, f"u_band_{channel}", table.band_to_rgb[i])
        light = self.lighting
        _uniform(program, "u_lighting").value = light.enabled
        _uniform(program, "u_light_dir").value = tuple(float(v) for v in light.direction())
        for name in ("ambient", "relief", "specular", "shininess"):
            _uniform(program, f"u_{name}").value = float(getattr(light, name))

    # --- drawing ------------------------------------------------------------------------------
    def _offscreen(self, size: tuple[int, int]) -> moderngl.Framebuffer:
        if self._target is None or self._target.size != tuple(size):
            if self._target is not None:
                self._target.color_attachments[0].release()
                self._target.release()
            w, h = size
            colour = self.ctx.renderbuffer((w, h), 4, dtype="f4")
            self._target = self.ctx.framebuffer(color_attachments=[colour])
        return self._target

    def render(
        self,
        size: tuple[int, int] | None = None,
        view: View | None = None,
        outlines: Sequence[BrushOutline] = (),
        arrows: Sequence[ForceArrow] = (),
        framebuffer: moderngl.Framebuffer | None = None,
        box: Box | None = None,
        fill: tuple[float, float, float, float] | None = None,
    ) -> None:
        """Draw the canvas (as last updated) and overlays.

        Args:
            size: output (W, H) pixels; default the canvas's pixels (or the framebuffer's size).
            view: canvas rectangle shown; default the whole canvas.
            outlines, arrows: brush outlines and force arrows to draw on top.
            framebuffer: target (e.g. a window's); default an offscreen RGBA32F target that
                :meth:`read_linear_rgba` reads back.
            box: draw only the pixels of this box (x0, y0, x1, y1); the others keep what the
                target held, or ``fill``.
            fill: the colour the whole target is cleared to first (default the background).
        """
        textures = self._textures
        if textures is None:
            raise RuntimeError("call update(canvas) before render()")
        if framebuffer is None:
            framebuffer = self._offscreen(size or textures.pixels)
        size = size or framebuffer.size
        view = view or ViewRect.whole(self._canvas_size_m)
        framebuffer.use()
        self.ctx.viewport = (0, 0, *size)
        self.ctx.disable(moderngl.BLEND | moderngl.DEPTH_TEST)
        if fill is not None or box is None:
            framebuffer.clear(*(fill or BACKGROUND))
        program = self._canvas_program(textures.layers)
        self._set_uniforms(program, view)
        textures.concentration.use(0)
        textures.surface.use(1)
        self._write_canvas_quad()
        if box is not None:
            self.ctx.scissor = (box[0], box[1], box[2] - box[0], box[3] - box[1])
        try:
            self._canvas_vao(textures.layers, program).render(moderngl.TRIANGLE_STRIP)
        finally:
            self.ctx.scissor = None
        self._draw_overlays(view, size, outlines, arrows)

    def render_cached(
        self,
        size: tuple[int, int],
        view: View,
        outlines: Sequence[BrushOutline] = (),
        arrows: Sequence[ForceArrow] = (),
        framebuffer: moderngl.Framebuffer | None = None,
    ) -> Box | None:
        """As :meth:`render`, drawing the cached picture (see the module docstring); returns the
        texel box shaded for this frame (None when the picture was up to date in sight). Only
        the stale texels in sight are shaded; those out of sight wait for a view that shows
        them. Magnified, the picture's texels are drawn sharp (nearest texel)."""
        textures = self._textures
        if textures is None:
            raise RuntimeError("call update(canvas) before render_cached()")
        sight = texel_box_in_sight(view.visible_box_m(), self._texel_m, textures.pixels)
        shaded = self._shade_stale(textures, sight)
        if framebuffer is None:
            framebuffer = self._offscreen(size)
        assert self._picture is not None
        framebuffer.use()
        self.ctx.viewport = (0, 0, *size)
        self.ctx.disable(moderngl.BLEND | moderngl.DEPTH_TEST)
        framebuffer.clear(*BACKGROUND)
        program = self._picture_program
        _uniform(program, "u_view").write(view.matrix().T.copy().tobytes())
        _uniform(program, "u_canvas_size_m").value = self._canvas_size_m
        _uniform(program, "u_picture").value = 0
        self._picture.use(0)
        self._write_canvas_quad()
        self._picture_vao.render(moderngl.TRIANGLE_STRIP)
        self._draw_overlays(view, size, outlines, arrows)
        return shaded

    def _shade_stale(self, textures: CanvasTextures, sight: Box | None = None) -> Box | None:
        """Bring the cached picture up to date in ``sight`` (texture texels; None for all of
        it): shade its stale texels there (all of them for a new canvas size or a new light)."""
        w, h = textures.pixels
        if self._picture is None or self._picture.size != (w, h):
            self._release_picture()
            self._picture = self.ctx.texture((w, h), 4, dtype="f2")
            # minified (not drawn so by the window) filtered, magnified each texel sharp
            self._picture.filter = (moderngl.LINEAR, moderngl.NEAREST)
            self._picture.repeat_x = False
            self._picture.repeat_y = False
            self._picture_fbo = self.ctx.framebuffer(color_attachments=[self._picture])
            self._stale = [(0, 0, w, h)]
        if self._picture_lighting != self.lighting:
            self._picture_lighting = self.lighting
            self._stale = [(0, 0, w, h)]
        boxes, self._stale = split_stale(self._stale, sight)
        if not boxes:
            return None
        assert self._picture_fbo is not None
        self._picture_fbo.use()
        self.ctx.viewport = (0, 0, w, h)
        self.ctx.disable(moderngl.BLEND | moderngl.DEPTH_TEST)
        program = self._canvas_program(textures.layers)
        self._set_uniforms(program, ViewRect.whole(self._canvas_size_m))
        textures.concentration.use(0)
        textures.surface.use(1)
        self._write_canvas_quad()
        shaded: Box | None = None
        try:
            for box in boxes:
                x0, y0, x1, y1 = box
                self.ctx.scissor = (x0, y0, x1 - x0, y1 - y0)
                self._canvas_vao(textures.layers, program).render(moderngl.TRIANGLE_STRIP)
                shaded = union_box(shaded, box)
        finally:
            self.ctx.scissor = None
        return shaded

    def _write_canvas_quad(self) -> None:
        w, h = self._canvas_size_m
        self._quad.write(np.array([[0, 0], [w, 0], [0, h], [w, h]], np.float32).tobytes())

    def _canvas_vao(self, layers: int, program: moderngl.Program) -> moderngl.VertexArray:
        vao = self._quad_vaos.get(layers)
        if vao is None:
            vao = self.ctx.vertex_array(program, [(self._quad, "2f", "in_pos_m")])
            self._quad_vaos[layers] = vao
        return vao

    def _release_picture(self) -> None:
        if self._picture_fbo is not None:
            self._picture_fbo.release()
        if self._picture is not None:
            self._picture.release()
        self._picture = self._picture_fbo = None

    def _draw_overlays(
        self,
        view: View,
        size: tuple[int, int],
        outlines: Sequence[BrushOutline],
        arrows: Sequence[ForceArrow],
    ) -> None:
        pixel_m = view.metres_per_pixel(size)
        shapes = [(outline_triangles(o, pixel_m), o.color) for o in outlines]
        shapes += [(arrow_triangles(a, pixel_m), a.color) for a in arrows]
        if not shapes:
            return
        self.ctx.enable(moderngl.BLEND)
        self.ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        _uniform(self._overlay, "u_view").write(view.matrix().T.copy().tobytes())
        for triangles, color in shapes:
            if len(triangles) == 0:
                continue
            buffer = self.ctx.buffer(triangles.tobytes())
            vao = self.ctx.vertex_array(self._overlay, [(buffer, "2f", "in_pos_m")])
            _uniform(self._overlay, "u_color").value = tuple(float(c) for c in color)
            vao.render(moderngl.TRIANGLES)
            vao.release()
            buffer.release()
        self.ctx.disable(moderngl.BLEND)

    def read_linear_rgba(self, box: Box | None = None) -> np.ndarray:
        """The last offscreen render (or its pixels in ``box``) as linear RGBA, (H, W, 4)
        float32, row 0 = bottom."""
        if self._target is None:
            raise RuntimeError("nothing rendered offscreen yet")
        x0, y0, x1, y1 = box or (0, 0, *self._target.size)
        rgba = np.empty((y1 - y0, x1 - x0, 4), np.float32)
        viewport = (x0, y0, x1 - x0, y1 - y0)
        self._target.read_into(rgba, viewport, components=4, dtype="f4")  # into the array
        return rgba

    def render_linear_rgba(self, canvas: Canvas, **kwargs) -> np.ndarray:
        """``update`` + ``render`` (offscreen, 1 texel per pixel by default) + readback."""
        self.update(canvas)
        self.render(**kwargs)
        return self.read_linear_rgba()

    def release(self) -> None:
        """Free the GPU resources (the context itself is the caller's)."""
        if self._textures is not None:
            self._textures.release()
        if self._tooth is not None:
            self._tooth.release()
        for vao in (*self._quad_vaos.values(), self._picture_vao):
            vao.release()
        self._release_picture()
        for program in (*self._programs.values(), self._overlay, self._picture_program):
            program.release()
        self._quad.release()
        if self._target is not None:
            self._target.release()


def _as_uniform(member: object, name: str) -> moderngl.Uniform:
    if not isinstance(member, moderngl.Uniform):
        raise TypeError(f"{name!r} is a {type(member).__name__}, not a uniform")
    return member


def _uniform(program: moderngl.Program, name: str) -> moderngl.Uniform:
    """The uniform ``name`` of ``program`` (KeyError if the program has no such member)."""
    return _as_uniform(program[name], name)


def _write_vec4_array(program: moderngl.Program, name: str, values: np.ndarray) -> None:
    """Write a vec4 array uniform; the GLSL compiler may trim unused tail elements, so the data
    is cut to the active length."""
    member = program.get(name, None)
    if member is None:  # optimised out entirely
        return
    uniform = _as_uniform(member, name)
    data = np.asarray(values, np.float32).reshape(-1)[: 4 * uniform.array_length]
    uniform.write(data.tobytes())
