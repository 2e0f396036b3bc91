"""Haptics: force filtering, the 1 kHz servo loop, clocks, devices and force safety.

The painting session publishes the simulation's force into a :class:`ForceChannel`; a
:class:`ServoLoop` reads it every tick, filters and scales it, adds the rigid canvas contact,
makes it safe and writes it to a :class:`HapticDevice`, and publishes the device's state into a
:class:`StateChannel` for the session. See the modules for details:

- :mod:`.channel` ForceSample, ForceChannel, StateChannel
- :mod:`.filters` zero-order hold, linear interpolation, FIR window filter (paper section 4.2)
- :mod:`.clock`, :mod:`.metrics` VirtualClock, RealTimeClock, timing reports
- :mod:`.servo`, :mod:`.fluid`, :mod:`.contact`, :mod:`.safety`, :mod:`.velocity` the loop
- :mod:`.device` HapticDevice, DeviceInfo, DeviceState; :mod:`.simulated`, :mod:`.replay`,
  :mod:`.hid_device` (with :mod:`.hid_stylus`, :mod:`.hid_pid`, :mod:`.hid_transport`) drivers
"""

from paintapp.haptics.channel import ForceChannel, ForceSample, StateChannel
from paintapp.haptics.clock import Clock, RealTimeClock, VirtualClock
from paintapp.haptics.contact import ContactConfig
from paintapp.haptics.device import (
    DeviceError,
    DeviceInfo,
    DeviceNotFoundError,
    DeviceState,
    HapticDevice,
)
from paintapp.haptics.filters import FilterConfig, make_filter
from paintapp.haptics.fluid import FluidConfig
from paintapp.haptics.hid_device import HidDevice
from paintapp.haptics.replay import ReplayDevice
from paintapp.haptics.safety import SafetyConfig
from paintapp.haptics.servo import ServoConfig, ServoLoop, ServoReport
from paintapp.haptics.simulated import SimulatedDevice

__all__ = [
    "Clock",
    "ContactConfig",
    "DeviceError",
    "DeviceInfo",
    "DeviceNotFoundError",
    "DeviceState",
    "FilterConfig",
    "FluidConfig",
    "ForceChannel",
    "ForceSample",
    "HapticDevice",
    "HidDevice",
    "RealTimeClock",
    "ReplayDevice",
    "SafetyConfig",
    "ServoConfig",
    "ServoLoop",
    "ServoReport",
    "SimulatedDevice",
    "StateChannel",
    "VirtualClock",
    "make_filter",
]
