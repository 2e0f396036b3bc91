"""The painting window's view of the canvas: where it is centred, how far zoomed, how turned.

One :class:`CanvasView` maps widget pixels to canvas metres and back; the pen input, the strokes,
the brush outline, the force arrow, the paint grid outline and the GPU's view matrix all come from
it, so what is drawn under the pen is what the pen paints on.

Frames: widget pixels are logical (device-independent) pixels with x right and y down, from the
widget's top-left corner; canvas metres have x right and y up from the canvas's bottom-left
corner. The canvas appears on screen turned by ``angle_rad`` counter-clockwise about the
widget's centre, where the canvas point ``centre_m`` is shown::

    canvas = centre + R(-angle) (x - W/2, H/2 - y) * metres_per_px
    widget = (W/2 + u, H/2 - v)  with  (u, v) = R(angle) (canvas - centre) / metres_per_px

The zoom is device pixels per canvas texel (1.0 = 100 %: one texel on one device pixel, whatever
the display's device pixel ratio).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

#: Zoom limits, device pixels per canvas texel (5 % and 1600 %).
MIN_ZOOM = 0.05
MAX_ZOOM = 16.0
#: Pixels kept free around the canvas by :meth:`CanvasView.fit`.
FIT_MARGIN_PX = 12


@dataclass(frozen=True)
class CanvasView:
    """A view of the canvas in a widget (see the module docstring).

    Attributes:
        centre_m: canvas point (x, y), metres, shown at the widget's centre.
        metres_per_px: canvas metres per logical widget pixel (> 0).
        angle_rad: turn of the canvas on screen, counter-clockwise.
        widget_px: (W, H) of the widget, logical pixels (at least 1 each).
    """

    centre_m: tuple[float, float]
    metres_per_px: float
    angle_rad: float = 0.0
    widget_px: tuple[int, int] = (1, 1)

    def __post_init__(self) -> None:
        values = (*self.centre_m, self.metres_per_px, self.angle_rad)
        if not all(math.isfinite(v) for v in values) or self.metres_per_px <= 0.0:
            raise ValueError(f"a view needs a finite centre, scale and angle, got {self}")
        if min(self.widget_px) < 1:
            raise ValueError(f"a view needs a widget of at least 1 x 1 pixel, got {self.widget_px}")

    # --- construction ---------------------------------------------------------------------------
    @classmethod
    def fit(
        cls,
        canvas_size_m: tuple[float, float],
        widget_px: tuple[int, int],
        angle_rad: float = 0.0,
        margin_px: int = FIT_MARGIN_PX,
    ) -> CanvasView:
        """The whole canvas (turned by ``angle_rad``) centred in the widget, aspect kept, with
        ``margin_px`` free around it."""
        width, height = max(int(widget_px[0]), 1), max(int(widget_px[1]), 1)
        w_m, h_m = float(canvas_size_m[0]), float(canvas_size_m[1])
        c, s = abs(math.cos(angle_rad)), abs(math.sin(angle_rad))
        span_x, span_y = c * w_m + s * h_m, s * w_m + c * h_m  # the turned canvas's extent
        free_w, free_h = max(width - 2 * margin_px, 1), max(height - 2 * margin_px, 1)
        per_px = max(span_x / free_w, span_y / free_h)
        return cls((0.5 * w_m, 0.5 * h_m), per_px, angle_rad, (width, height))

    def resized(self, widget_px: tuple[int, int]) -> CanvasView:
        """The same centre, scale and angle in a widget of another size."""
        size = (max(int(widget_px[0]), 1), max(int(widget_px[1]), 1))
        return self if size == self.widget_px else replace(self, widget_px=size)

    def zoomed(self, factor: float, anchor_px: tuple[float, float] | None = None) -> CanvasView:
        """Magnified ``factor`` times about widget point ``anchor_px`` (default the centre):
        the canvas point under the anchor stays there."""
        if not (math.isfinite(factor) and factor > 0.0):
            return self
        return self._scaled_to(self.metres_per_px / factor, anchor_px)

    def panned(self, dx_px: float, dy_px: float) -> CanvasView:
        """The canvas moved by (dx, dy) widget pixels on screen (it follows a dragging hand)."""
        if not (math.isfinite(dx_px) and math.isfinite(dy_px)):
            return self
        ux, uy = _turn(-dx_px, dy_px, -self.angle_rad)
        cx, cy = self.centre_m
        return replace(self, centre_m=(cx + ux * self.metres_per_px, cy + uy * self.metres_per_px))

    def rotated(self, delta_rad: float, anchor_px: tuple[float, float] | None = None) -> CanvasView:
        """The canvas turned by ``delta_rad`` more (counter-clockwise on screen) about widget
        point ``anchor_px`` (default the centre), which keeps its canvas point."""
        if not math.isfinite(delta_rad):
            return self
        anchor = self._anchor(anchor_px)
        held = self.to_canvas(*anchor)
        angle = math.remainder(self.angle_rad + delta_rad, 2.0 * math.pi)
        return replace(self, angle_rad=angle)._keeping(held, anchor)

    def with_angle(
        self, angle_rad: float, anchor_px: tuple[float, float] | None = None
    ) -> CanvasView:
        """The canvas turned to ``angle_rad`` about ``anchor_px`` (default the centre)."""
        return self.rotated(angle_rad - self.angle_rad, anchor_px)

    def with_zoom(
        self,
        zoom: float,
        texel_m: float,
        ratio: float,
        anchor_px: tuple[float, float] | None = None,
    ) -> CanvasView:
        """The view at ``zoom`` (device pixels per texel, clamped to [MIN_ZOOM, MAX_ZOOM]) about
        ``anchor_px``, for canvas texels ``texel_m`` wide on a display of device pixel ratio
        ``ratio``."""
        zoom = min(max(zoom, MIN_ZOOM), MAX_ZOOM)
        return self._scaled_to(texel_m * ratio / zoom, anchor_px)

    def zoom(self, texel_m: float, ratio: float) -> float:
        """Device pixels per canvas texel (1.0 = 100 %)."""
        return texel_m * ratio / self.metres_per_px

    def clamped(self, texel_m: float, ratio: float) -> CanvasView:
        """This view with its zoom held within [MIN_ZOOM, MAX_ZOOM] about the centre."""
        zoom = self.zoom(texel_m, ratio)
        if MIN_ZOOM <= zoom <= MAX_ZOOM:
            return self
        return self.with_zoom(zoom, texel_m, ratio)

    # --- mapping --------------------------------------------------------------------------------
    def to_canvas(self, x_px: float, y_px: float) -> tuple[float, float]:
        """Widget pixel (y down) to canvas metres (y up)."""
        w, h = self.widget_px
        ux, uy = _turn(x_px - 0.5 * w, 0.5 * h - y_px, -self.angle_rad)
        cx, cy = self.centre_m
        return cx + ux * self.metres_per_px, cy + uy * self.metres_per_px

    def to_widget(self, x_m: float, y_m: float) -> tuple[float, float]:
        """Canvas metres (y up) to widget pixels (y down)."""
        cx, cy = self.centre_m
        u, v = _turn(
            (x_m - cx) / self.metres_per_px, (y_m - cy) / self.metres_per_px, self.angle_rad
        )
        w, h = self.widget_px
        return 0.5 * w + u, 0.5 * h - v

    def to_widget_array(self, points_m: np.ndarray) -> np.ndarray:
        """:meth:`to_widget` of points (N, 2), metres; returns (N, 2) float64 pixels."""
        p = np.asarray(points_m, np.float64).reshape(-1, 2) - np.asarray(self.centre_m)
        c, s = math.cos(self.angle_rad), math.sin(self.angle_rad)
        u = (c * p[:, 0] - s * p[:, 1]) / self.metres_per_px
        v = (s * p[:, 0] + c * p[:, 1]) / self.metres_per_px
        w, h = self.widget_px
        return np.stack([0.5 * w + u, 0.5 * h - v], axis=1)

    def widget_box(
        self, box_m: tuple[float, float, float, float]
    ) -> tuple[float, float, float, float]:
        """The widget-pixel rectangle (left, top, right, bottom) bounding canvas rectangle
        ``box_m`` (x0, y0, x1, y1), metres (its four corners, turned)."""
        x0, y0, x1, y1 = box_m
        xy = self.to_widget_array(np.array([[x0, y0], [x1, y0], [x0, y1], [x1, y1]]))
        lo, hi = xy.min(axis=0), xy.max(axis=0)
        return float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1])

    def corners_px(self, box_m: tuple[float, float, float, float]) -> np.ndarray:
        """The widget pixels (4, 2) of canvas rectangle ``box_m``'s corners, in order round it
        (bottom-left, bottom-right, top-right, top-left in canvas terms)."""
        x0, y0, x1, y1 = box_m
        return self.to_widget_array(np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]]))

    def visible_box_m(self) -> tuple[float, float, float, float]:
        """The canvas rectangle (x0, y0, x1, y1), metres, bounding what the widget shows."""
        w, h = self.widget_px
        points = [self.to_canvas(x, y) for x, y in ((0, 0), (w, 0), (0, h), (w, h))]
        xs, ys = [p[0] for p in points], [p[1] for p in points]
        return min(xs), min(ys), max(xs), max(ys)

    # --- the GPU's side -------------------------------------------------------------------------
    def matrix(self) -> np.ndarray:
        """3x3 matrix taking (x_m, y_m, 1) to clip coordinates (row-major, as maths writes it):
        the same map as :meth:`to_widget`, scaled to [-1, 1] across the widget (y up)."""
        w, h = self.widget_px
        sx, sy = 2.0 / (w * self.metres_per_px), 2.0 / (h * self.metres_per_px)
        c, s = math.cos(self.angle_rad), math.sin(self.angle_rad)
        cx, cy = self.centre_m
        turn = np.array([[sx * c, -sx * s], [sy * s, sy * c]])
        shift = -turn @ np.array([cx, cy])
        m = np.array([[*turn[0], shift[0]], [*turn[1], shift[1]], [0.0, 0.0, 1.0]])
        return m.astype(np.float32)

    def metres_per_pixel(self, size: tuple[int, int]) -> float:
        """Canvas metres per output pixel for an output (W, H) covering the widget (device
        pixels: the widget's size times its device pixel ratio)."""
        return self.metres_per_px * self.widget_px[0] / max(size[0], 1)

    # --- helpers --------------------------------------------------------------------------------
    def _anchor(self, anchor_px: tuple[float, float] | None) -> tuple[float, float]:
        if anchor_px is None or not all(math.isfinite(v) for v in anchor_px):
            return 0.5 * self.widget_px[0], 0.5 * self.widget_px[1]
        return float(anchor_px[0]), float(anchor_px[1])

    def _keeping(self, point_m: tuple[float, float], anchor: tuple[float, float]) -> CanvasView:
        """This view moved so that canvas point ``point_m`` shows at widget point ``anchor``."""
        now = self.to_canvas(*anchor)
        cx, cy = self.centre_m
        return replace(self, centre_m=(cx + point_m[0] - now[0], cy + point_m[1] - now[1]))

    def _scaled_to(self, metres_per_px: float, anchor_px: tuple[float, float] | None) -> CanvasView:
        if not (math.isfinite(metres_per_px) and metres_per_px > 0.0):
            return self
        anchor = self._anchor(anchor_px)
        held = self.to_canvas(*anchor)
        return replace(self, metres_per_px=metres_per_px)._keeping(held, anchor)


def _turn(x: float, y: float, angle_rad: float) -> tuple[float, float]:
    """(x, y) turned counter-clockwise by ``angle_rad``."""
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return c * x - s * y, s * x + c * y
