"""The status bar's permanent text: what an artist needs while painting."""

from __future__ import annotations

import math


def view_status_text(
    brush: str, brush_scale: float, pigment: str, zoom_percent: float, angle_deg: float
) -> str:
    """One line: the brush and its size, the pigment last loaded, the zoom (% of one canvas
    texel per device pixel) and the canvas's turn (degrees counter-clockwise)."""
    zoom = f"{zoom_percent:.0f} %" if zoom_percent >= 10 else f"{zoom_percent:.1f} %"
    turn = 0.0 if not math.isfinite(angle_deg) or abs(angle_deg) < 0.05 else angle_deg
    return f"brush {brush} x{brush_scale:.2g}   pigment {pigment}   zoom {zoom}   turn {turn:.0f}\u00b0"
