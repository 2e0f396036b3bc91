"""Haptics: force filtering, the 1 kHz servo loop, clocks, force safety; device drivers apart.

The painting session publishes the simulation's force into a
:class:`~paintapp.haptics.channel.ForceChannel`; a :class:`~paintapp.haptics.servo.ServoLoop`
reads it every tick, filters and scales it, adds the rigid canvas contact, makes it safe and
writes it to a :class:`~paintapp.haptics.device.HapticDevice`, and publishes the device's state
into a :class:`~paintapp.haptics.channel.StateChannel` for the session. The modules:

- :mod:`.channel` ForceSample, ForceChannel, StateChannel
- :mod:`.filters` zero-order hold, linear interpolation, FIR window filter (paper section 4.2)
- :mod:`.clock`, :mod:`.metrics` VirtualClock, RealTimeClock, timing reports
- :mod:`.servo`, :mod:`.fluid`, :mod:`.contact`, :mod:`.safety`, :mod:`.velocity` the loop's
  stages; :mod:`.tick_log` its record of each tick
- :mod:`.device` the device interface: HapticDevice, DeviceInfo, DeviceState
- :mod:`.orientation` stylus quaternion <-> tablet tilt and twist
- :mod:`.process`, :mod:`.shared_state`, :mod:`.realtime` the loop in a process of its own (the
  window's form): shared-memory seqlock channels, real-time priority, fail-safe exits
- :mod:`.bare_loop` the machine's own timing floor: the servo process's clock with nothing to do
- :mod:`.synthetic` a synthetic force source (checks and tests)
- :mod:`.devices` the drivers: simulated hand, stroke-file playback, USB HID, vendor libraries

Nothing here imports numba, GL, Qt or the solver: ``import paintapp.haptics.servo`` starts light.
This package's ``__init__`` imports nothing; import names from their modules.
"""
