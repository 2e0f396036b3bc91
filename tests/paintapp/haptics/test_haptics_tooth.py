"""The canvas contact follows the tooth: felt at its spatial frequency, within the device's limits."""

from __future__ import annotations

import math

import numpy as np
import pytest

from common.errors import InputError
from common.surfaces import surface_spec
from paintapp.haptics.clock import VirtualClock
from paintapp.haptics.contact import CanvasContact, ContactConfig
from paintapp.haptics.device import DeviceInfo, DeviceState
from paintapp.haptics.devices.simulated import SIMULATED_INFO
from paintapp.haptics.safety import SafetyConfig
from paintapp.haptics.servo import ServoConfig, ServoLoop

DEPTH_M = 0.0005  # the tip held half a millimetre into the canvas
SETTLE_S = 0.2  # the safety stage's ramp is over by then


class DragDevice:
    """Drags the tip along +x at ``speed`` m/s, ``DEPTH_M`` below the canvas; records writes.
    ``bad_ticks``: reads that report a non-finite position."""

    def __init__(self, clock: VirtualClock, speed: float, bad_ticks: tuple[int, ...] = ()):
        self.clock, self.speed, self.bad_ticks = clock, speed, set(bad_ticks)
        self.reads, self.writes = 0, []

    @property
    def info(self) -> DeviceInfo:
        return SIMULATED_INFO

    def open(self) -> None: ...

    def close(self) -> None: ...

    def position(self, t_s: float) -> np.ndarray:
        return np.array([0.002 + self.speed * t_s, 0.0123, -DEPTH_M])

    def read(self) -> DeviceState:
        self.reads += 1
        t = self.clock.now_s()
        pos = self.position(t)
        if self.reads in self.bad_ticks:
            pos[0] = math.nan
        return DeviceState(t, pos, pressure=0.0)

    def write(self, force_n: np.ndarray, torque_nm: np.ndarray) -> None:
        self.writes.append(force_n.copy())


def drag(surface: str, speed: float, seconds: float, bad_ticks: tuple[int, ...] = ()):
    """Run the servo loop over a drag; (positions x (m), forces (n, 3) N written, the loop)."""
    clock = VirtualClock()
    device = DragDevice(clock, speed, bad_ticks)
    config = ServoConfig(
        safety=SafetyConfig(ramp_time_s=0.05), contact=ContactConfig(surface=surface)
    )
    loop = ServoLoop(device, config=config)
    loop.open()
    clock.run(lambda i, t: loop.tick(t), round(seconds / clock.period_s))
    forces = np.array(device.writes)
    t = np.arange(len(forces)) * clock.period_s
    return 0.002 + speed * t, forces, loop


def over_limit_or_bad(forces: np.ndarray) -> int:
    """Writes that are non-finite or beyond the device's force limit."""
    finite = np.all(np.isfinite(forces), axis=1)
    norm = np.linalg.norm(np.where(finite[:, None], forces, 0.0), axis=1)
    return int(np.count_nonzero(~finite | (norm > SIMULATED_INFO.max_force_n * (1 + 1e-12))))


def dominant_wavelength_mm(x_m: np.ndarray, f: np.ndarray) -> float:
    """The wavelength (mm) of the strongest component of ``f`` sampled along ``x_m``."""
    f = (f - f.mean()) * np.hanning(len(f))
    spectrum = np.abs(np.fft.rfft(f))
    freq = np.fft.rfftfreq(len(f), d=(x_m[1] - x_m[0]) * 1e3)  # cycles per mm
    k = int(np.argmax(spectrum[1:])) + 1
    return float(1.0 / freq[k])


@pytest.mark.parametrize("surface", ["cotton_duck", "fine_linen"])
def test_the_felt_force_varies_at_the_thread_pitch(surface):
    x, forces, _ = drag(surface, speed=0.02, seconds=1.2)
    assert over_limit_or_bad(forces) == 0
    settled = slice(round(SETTLE_S / 1e-3), None)
    fz = forces[settled, 2]
    k = 0.5 * SIMULATED_INFO.max_stiffness_n_per_m
    assert fz.min() > 0.0  # still in contact everywhere: the tooth is far shallower than 0.5 mm
    relief = surface_spec(surface).relief_um * 1e-6
    # felt (the tip's rounding takes most of fine linen's 0.35 mm threads), no more than the relief
    assert 0.05 * k * relief < np.ptp(fz) <= 1.05 * k * relief
    pitch = surface_spec(surface).pitch_mm
    wavelength = dominant_wavelength_mm(x[settled], fz)
    # the threads pass under the tip every pitch, the weave repeats every two
    assert min(abs(wavelength - pitch), abs(wavelength - 2 * pitch)) < 0.15 * pitch


def test_a_smooth_canvas_feels_flat_and_unchanged():
    _, forces, loop = drag("smooth", speed=0.02, seconds=0.5)
    k = 0.5 * SIMULATED_INFO.max_stiffness_n_per_m
    np.testing.assert_allclose(forces[-200:, 2], k * DEPTH_M, rtol=1e-12)
    assert loop.contact.tooth is None and loop.contact.tooth_z_m == 0.0


def test_a_fast_drag_over_rough_paper_stays_within_the_slope_limit():
    # 0.5 m/s over cold-press paper: 0.5 mm per tick, bumps of 0.3-3 mm
    _, forces, loop = drag("cold_press", speed=0.5, seconds=0.3, bad_ticks=(150, 151, 260))
    assert over_limit_or_bad(forces) == 0
    contact = loop.log.arrays()["contact_force_n"][:, 2]
    bound = loop.config.contact.tooth_step_fraction * SIMULATED_INFO.max_force_n
    steps = np.abs(np.diff(contact[50:]))
    assert steps.max() <= bound * (1 + 1e-9)
    counts = loop.safety.counters()
    assert counts["nonfinite"] == 0 and counts["clamped"] == 0  # a bad reading keeps the height


def test_the_tooth_filters_are_bounded_per_tick():
    info = SIMULATED_INFO
    contact = CanvasContact(info, ContactConfig(surface="cotton_duck"))
    k = contact.stiffness_n_per_m
    assert contact.tooth_step_m * k == pytest.approx(0.02 * info.max_force_n)
    heights = []
    for i in range(2000):
        contact.force(np.array([i * 1e-4, 0.0, -DEPTH_M]), np.zeros(3))  # 0.1 m/s
        heights.append(contact.tooth_z_m)
    assert np.all(np.abs(np.diff(heights)) <= contact.tooth_step_m + 1e-15)
    assert np.ptp(heights[500:]) <= surface_spec("cotton_duck").relief_um * 1e-6


def test_switching_surface_eases_the_wall_to_the_new_tooth():
    contact = CanvasContact(SIMULATED_INFO, ContactConfig(surface="cotton_duck"))
    contact.set_surface("cold_press", wait=True)
    assert contact.surface == "cold_press"
    contact.set_surface("smooth")
    for _ in range(200):
        contact.force(np.array([0.01, 0.01, -DEPTH_M]), np.zeros(3))
    assert contact.surface == "smooth" and abs(contact.tooth_z_m) < 1e-9


def test_contact_config_rejects_unknown_surfaces_and_bad_filters():
    with pytest.raises(InputError, match="unknown surface"):
        ContactConfig(surface="velvet")
    with pytest.raises(InputError):
        ContactConfig(tooth_cutoff_hz=math.nan)
