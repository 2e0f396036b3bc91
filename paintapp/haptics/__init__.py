"""Haptics: force filtering, the 1 kHz servo loop, clocks, force safety; device drivers apart.

The painting session publishes the simulation's force into a
:class:`~paintapp.haptics.channel.ForceChannel`; a :class:`~paintapp.haptics.servo.ServoLoop`
reads it every tick, filters and scales it, adds the rigid canvas contact, makes it safe and
writes it to a :class:`~paintapp.haptics.device.HapticDevice`, and publishes the device's state
into a :class:`~paintapp.haptics.channel.StateChannel` for the session. The modules:

- :mod:`.channel` ForceSample and the channels; :mod:`.device` the device interface (HapticDevice)
- :mod:`.filters` hold, linear and FIR window filters (paper section 4.2); :mod:`.orientation`
  stylus quaternion <-> tablet tilt and twist; :mod:`.synthetic` a synthetic force source
- :mod:`.servo`, :mod:`.fluid`, :mod:`.contact`, :mod:`.safety`, :mod:`.velocity` the loop's
  stages, :mod:`.tick_log` its record of each tick; :mod:`.clock`, :mod:`.metrics` timing
- :mod:`.process`, :mod:`.shared_state`, :mod:`.realtime` the loop in a process of its own
  (seqlock channels, real-time priority, fail-safe exits); :mod:`.bare_loop` its timing floor
- :mod:`.devices` the drivers: simulated hand, stroke-file playback, USB HID, vendor libraries

Nothing here imports numba, GL, Qt or the solver; ``__init__`` imports nothing (use the modules).
"""
