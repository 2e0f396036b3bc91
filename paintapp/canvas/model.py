"""The canvas: per-texel paint volume per pigment and wetness, with dirty-region tracking.

Coordinates (a right-handed frame seen from the painter): the origin is the canvas's bottom-left
corner, x points right, y points up, z points out of the canvas towards the painter. Texel
``(ix, iy)`` covers ``[ix dx, (ix + 1) dx) x [iy dy, (iy + 1) dy)`` metres, so array row ``iy``
grows *upwards*; image files store the top row first (they are flipped on write/read).

Arrays:
    paint_m:  (P, H, W) float32, volume of each pigment's paint per unit area, metres of thickness.
    wetness:  (H, W) float32 in [0, 1]; 1 is fresh paint, 0 is dry (dry paint no longer moves).

Derived: ``height_m`` (H, W) is the total paint thickness; ``concentration`` (P, H, W) the volume
fraction of each pigment (0 where the canvas is bare).

The ground under the paint is ``surface``, the name of a bundled canvas surface
(:mod:`paintapp.canvas.surfaces`; ``smooth``, the flat plane, by default); ``tooth_m`` (H, W) is
its height at each texel, metres (zero-mean; zeros on ``smooth``), built on first use.

Writers (paint transfer, file loading) should go through :meth:`Canvas.write_region`, which clips,
rejects or zeroes non-finite values and marks the region dirty for the renderer.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from common.errors import InputError
from common.names import check_pigment_name
from paintapp.canvas.regions import Box, box_of_nonzero, clip_box, union_box
from paintapp.canvas.surfaces import SMOOTH, canvas_tooth, surface_spec

MAX_PIXELS = 4096
MAX_PIGMENTS = 16
#: Wetness below this becomes exactly 0 (dry) when drying.
DRY_THRESHOLD = 1e-3
#: Relative wetness drop after which drying marks the wet area dirty (for the renderer).
DRY_UPLOAD_STEP = 0.02
#: Relative wetness drop that drying gathers before it touches the texels: steps of a slow drying
#: (1 % per second) cost a pass over the wet area only every half second, not every paint step.
DRY_BATCH = 0.005
#: Thickest paint accepted, metres (a 5 cm blob is already absurd for a painting).
MAX_PAINT_M = 0.05
#: Thinnest film of paint that counts as paint (0.1 um: far below any visible layer); the paint
#: transfer leaves no changed column with less, and a texel with at most this much is unpainted.
FILM_FLOOR_M = 1e-7


def _check_name(name: str) -> None:
    """Pigment names follow :data:`common.names.PIGMENT_NAME` (they become EXR channel names)."""
    try:
        check_pigment_name(name)
    except ValueError as exc:
        raise InputError(str(exc), key="pigment") from None


@dataclass(eq=False)
class Canvas:
    """Paint on a rectangular canvas (see the module docstring for frames and shapes).

    Args:
        pixels: (W, H) texel counts, each in [1, 4096].
        size_m: (w, h) physical size, metres, each > 0.
        pigment_names: the pigment of each paint channel, in order (at most 16, unique).
        paint_m: (P, H, W) paint thickness per pigment, metres; zeros if omitted.
        wetness: (H, W) in [0, 1]; zeros (dry) if omitted.
        surface: the canvas surface (:mod:`paintapp.canvas.surfaces`), ``smooth`` if omitted.
    """

    pixels: tuple[int, int]
    size_m: tuple[float, float]
    pigment_names: tuple[str, ...] = ()
    paint_m: np.ndarray = None  # type: ignore[assignment]
    wetness: np.ndarray = None  # type: ignore[assignment]
    surface: str = SMOOTH
    _tooth: np.ndarray | None = field(default=None, init=False, repr=False)
    _dirty: Box | None = field(default=None, init=False, repr=False)
    _wet_dirty: Box | None = field(default=None, init=False, repr=False)
    _wet_box: Box | None = field(default=None, init=False, repr=False)
    _unshown_drying: float = field(default=1.0, init=False, repr=False)
    _pending_drying: float = field(default=1.0, init=False, repr=False)

    def __post_init__(self) -> None:
        w, h = (int(v) for v in self.pixels)
        if not (1 <= w <= MAX_PIXELS and 1 <= h <= MAX_PIXELS) or (w, h) != tuple(self.pixels):
            raise InputError(
                f"canvas pixels must be integers in [1, {MAX_PIXELS}], got {self.pixels}",
                key="pixels",
            )
        sw, sh = (float(v) for v in self.size_m)
        if not (math.isfinite(sw) and math.isfinite(sh) and sw > 0 and sh > 0):
            raise InputError(
                f"canvas size must be finite and > 0 m, got {self.size_m}", key="size_m"
            )
        self.pixels, self.size_m = (w, h), (sw, sh)
        self.pigment_names = tuple(self.pigment_names)
        for name in self.pigment_names:
            _check_name(name)
        if len(set(self.pigment_names)) != len(self.pigment_names):
            raise InputError(f"duplicate pigment names {self.pigment_names}", key="pigment_names")
        if len(self.pigment_names) > MAX_PIGMENTS:
            raise InputError(f"at most {MAX_PIGMENTS} pigments per canvas", key="pigment_names")
        self.paint_m = self._checked(self.paint_m, (len(self.pigment_names), h, w), "paint_m")
        self.wetness = self._checked(self.wetness, (h, w), "wetness")
        if np.any(self.paint_m < 0) or np.any(self.paint_m > MAX_PAINT_M):
            raise InputError(f"paint thickness must be in [0, {MAX_PAINT_M}] m", key="paint_m")
        if np.any(self.wetness < 0) or np.any(self.wetness > 1):
            raise InputError("wetness must be in [0, 1]", key="wetness")
        self.surface = surface_spec(self.surface, key="surface").name
        self._wet_box = box_of_nonzero(self.wetness)
        self.mark_all_dirty()

    def __getstate__(self) -> dict:
        """Pickled (to the simulation process) without the tooth heights, rebuilt from the
        surface's name where needed."""
        state = self.__dict__.copy()
        state["_tooth"] = None
        return state

    @staticmethod
    def _checked(array: np.ndarray | None, shape: tuple[int, ...], key: str) -> np.ndarray:
        if array is None:
            return np.zeros(shape, np.float32)
        array = np.ascontiguousarray(array, dtype=np.float32)
        if array.shape != shape:
            raise InputError(f"expected shape {shape}, got {array.shape}", key=key)
        bad = int(np.count_nonzero(~np.isfinite(array)))
        if bad:
            raise InputError(f"{bad} non-finite value(s)", key=key)
        return array

    # --- geometry -------------------------------------------------------------------------------
    @property
    def width(self) -> int:
        return self.pixels[0]

    @property
    def height(self) -> int:
        return self.pixels[1]

    @property
    def texel_size_m(self) -> tuple[float, float]:
        """(dx, dy): size of one texel, metres."""
        return (self.size_m[0] / self.pixels[0], self.size_m[1] / self.pixels[1])

    def metres_to_texel(self, x_m: float | np.ndarray, y_m: float | np.ndarray):
        """Continuous texel coordinates of a point in metres; texel i spans [i, i + 1)."""
        dx, dy = self.texel_size_m
        return np.asarray(x_m) / dx, np.asarray(y_m) / dy

    def texel_to_metres(self, ix: float | np.ndarray, iy: float | np.ndarray):
        """Position in metres of the centre of texel (ix, iy) (fractional indices allowed)."""
        dx, dy = self.texel_size_m
        return (np.asarray(ix) + 0.5) * dx, (np.asarray(iy) + 0.5) * dy

    def texel_box_m(self, x0_m: float, y0_m: float, x1_m: float, y1_m: float) -> Box | None:
        """Half-open texel box [x0, x1) x [y0, y1) covering a rectangle in metres, clipped."""
        fx0, fy0 = self.metres_to_texel(x0_m, y0_m)
        fx1, fy1 = self.metres_to_texel(x1_m, y1_m)
        box = (math.floor(fx0), math.floor(fy0), math.ceil(fx1), math.ceil(fy1))
        return clip_box(box, self.pixels)

    # --- pigments -------------------------------------------------------------------------------
    def pigment_index(self, name: str) -> int:
        """Channel index of a pigment; InputError if the canvas has no such channel."""
        try:
            return self.pigment_names.index(name)
        except ValueError:
            raise InputError(f"canvas has no pigment {name!r}", key="pigment") from None

    def add_pigment(self, name: str) -> int:
        """Index of pigment ``name``, adding an empty channel for it if it is new."""
        if name in self.pigment_names:
            return self.pigment_names.index(name)
        _check_name(name)
        if len(self.pigment_names) >= MAX_PIGMENTS:
            raise InputError(f"at most {MAX_PIGMENTS} pigments per canvas", key="pigment")
        empty = np.zeros((1, self.height, self.width), np.float32)
        self.paint_m = np.concatenate([self.paint_m, empty], axis=0)
        self.pigment_names = (*self.pigment_names, name)
        return len(self.pigment_names) - 1

    # --- derived fields -------------------------------------------------------------------------
    @property
    def height_m(self) -> np.ndarray:
        """Total paint thickness, metres, (H, W) float32 (computed on each call)."""
        return self.paint_m.sum(axis=0, dtype=np.float32)

    @property
    def has_tooth(self) -> bool:
        """True unless the surface is the flat ``smooth``."""
        return not surface_spec(self.surface).flat

    @property
    def tooth_m(self) -> np.ndarray:
        """Height of the surface at each texel, metres, (H, W) float32, zero-mean (zeros on
        ``smooth``); built once and shared by the canvases of the same surface and size (read
        only)."""
        if self._tooth is None:
            self._tooth = canvas_tooth(self.surface, self.pixels, self.texel_size_m)
        return self._tooth

    @property
    def concentration(self) -> np.ndarray:
        """Volume fraction of each pigment, (P, H, W) float32, 0 where there is no paint."""
        return self.concentration_region((0, 0, self.width, self.height))

    def concentration_region(self, box: Box) -> np.ndarray:
        """Concentrations inside a texel box, shape (P, y1 - y0, x1 - x0) float32."""
        x0, y0, x1, y1 = box
        paint = self.paint_m[:, y0:y1, x0:x1]
        total = paint.sum(axis=0, dtype=np.float32)
        out = np.zeros(paint.shape, np.float32)
        return np.divide(paint, total, out=out, where=total > 0)

    # --- writing ----------------------------------------------------------------------------------
    def write_region(
        self,
        x0: int,
        y0: int,
        paint_m: np.ndarray,
        wetness: np.ndarray | None = None,
        *,
        strict: bool = False,
    ) -> int:
        """Overwrite a block of texels whose lower-left texel is (x0, y0); clipped to the canvas.

        Args:
            paint_m: (P, h, w) new paint thickness per pigment, metres.
            wetness: (h, w) new wetness; unchanged if None.
            strict: raise :class:`InputError` on non-finite input instead of zeroing it.

        Returns:
            The number of non-finite values replaced by 0. Negative paint is clamped to 0 and
            wetness to [0, 1].
        """
        paint = np.asarray(paint_m, np.float32)
        if paint.ndim != 3 or paint.shape[0] != len(self.pigment_names):
            raise InputError(
                f"expected paint of shape (P={len(self.pigment_names)}, h, w)", key="paint_m"
            )
        h, w = paint.shape[1:]
        if wetness is not None and np.shape(wetness) != (h, w):
            raise InputError(f"expected wetness of shape {(h, w)}", key="wetness")
        box = clip_box((x0, y0, x0 + w, y0 + h), self.pixels)
        if box is None:
            return 0
        bx0, by0, bx1, by1 = box
        src = (slice(by0 - y0, by1 - y0), slice(bx0 - x0, bx1 - x0))
        bad = _store(self.paint_m[:, by0:by1, bx0:bx1], paint[:, src[0], src[1]], 0.0, MAX_PAINT_M)
        if wetness is not None:
            wet = np.asarray(wetness, np.float32)[src]
            bad += _store(self.wetness[by0:by1, bx0:bx1], wet, 0.0, 1.0)
        if bad and strict:
            raise InputError(f"{bad} non-finite value(s) in a canvas write", key="paint_m")
        self.mark_dirty(*box)
        return bad

    def dry(self, dt_s: float, rate_per_s: float) -> None:
        """Let paint dry: wetness decays as ``exp(-rate dt)``; below 1e-3 it becomes exactly 0.

        Only the bounding box of possibly-wet texels is touched, and only once the decay gathered
        since the last pass reaches ``DRY_BATCH`` (0.5 %): the wetness lags its exact value by
        less than that (paint laid meanwhile dries as if laid at the last pass). The box is marked
        wetness-dirty (:meth:`take_wet_dirty`: only the wetness changed there) once the wetness
        has dropped by 2 % since it was last marked (and when it becomes fully dry), so slow
        drying does not re-upload the wet area every frame, nor its paint ever.
        """
        if not (math.isfinite(dt_s) and math.isfinite(rate_per_s)) or dt_s < 0 or rate_per_s < 0:
            raise InputError(f"need finite dt_s >= 0 and rate >= 0, got {dt_s}, {rate_per_s}")
        if self._wet_box is None or dt_s == 0 or rate_per_s == 0:
            return
        self._pending_drying *= math.exp(-rate_per_s * dt_s)
        if self._pending_drying > 1.0 - DRY_BATCH:
            return
        factor, self._pending_drying = self._pending_drying, 1.0
        x0, y0, x1, y1 = self._wet_box
        block = self.wetness[y0:y1, x0:x1]
        block *= np.float32(factor)
        block[block < DRY_THRESHOLD] = 0.0
        all_dry = not block.any()
        # Re-upload for the renderer only once wetness fell visibly (2 %) or the paint is dry.
        self._unshown_drying *= factor
        if all_dry or self._unshown_drying < 1.0 - DRY_UPLOAD_STEP:
            self.mark_wet_dirty(x0, y0, x1, y1)
            self._unshown_drying = 1.0
        if all_dry:
            self._wet_box = None

    # --- dirty region ---------------------------------------------------------------------------
    def mark_dirty(self, x0: int, y0: int, x1: int, y1: int) -> None:
        """Record that texels in [x0, x1) x [y0, y1) changed (clipped; merged into one box)."""
        box = clip_box((int(x0), int(y0), int(x1), int(y1)), self.pixels)
        if box is not None:
            self._dirty = union_box(self._dirty, box)
            self._wet_box = union_box(self._wet_box, box)

    def mark_all_dirty(self) -> None:
        """Record that the whole canvas changed."""
        self._dirty = (0, 0, self.width, self.height)

    def take_dirty(self) -> Box | None:
        """The box (x0, y0, x1, y1) changed since the last call, or None; clears it."""
        box, self._dirty = self._dirty, None
        return box

    def peek_dirty(self) -> Box | None:
        """The pending dirty box without clearing it."""
        return self._dirty

    def mark_wet_dirty(self, x0: int, y0: int, x1: int, y1: int) -> None:
        """Record that only the wetness changed in [x0, x1) x [y0, y1) (clipped; merged)."""
        box = clip_box((int(x0), int(y0), int(x1), int(y1)), self.pixels)
        if box is not None:
            self._wet_dirty = union_box(self._wet_dirty, box)

    def take_wet_dirty(self) -> Box | None:
        """The box where only the wetness changed since the last call, or None; clears it (the
        dirty box of :meth:`take_dirty` may overlap it)."""
        box, self._wet_dirty = self._wet_dirty, None
        return box

    def peek_wet_dirty(self) -> Box | None:
        """The pending wetness-only box without clearing it."""
        return self._wet_dirty


def _store(dst: np.ndarray, src: np.ndarray, lo: float, hi: float) -> int:
    """Copy src into dst, non-finite -> 0 and clamped to [lo, hi]; returns the non-finite count."""
    finite = np.isfinite(src)
    bad = int(src.size - np.count_nonzero(finite))
    np.clip(np.where(finite, src, np.float32(0)), lo, hi, out=dst)
    return bad
