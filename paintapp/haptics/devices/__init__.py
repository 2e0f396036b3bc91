"""Haptic device drivers behind :class:`paintapp.haptics.device.HapticDevice`: the simulated hand
(:mod:`.simulated`), stroke-file playback (:mod:`.stroke_player`), USB HID devices (:mod:`.hid`
over :mod:`.hid_transport`, speaking :mod:`.hid_stylus` or :mod:`.hid_pid` as the report
descriptor (:mod:`.hid_descriptor`) says), vendor libraries bound with :mod:`ctypes`
(:mod:`.vendor`; OpenHaptics' ``libHD``, :mod:`.openhaptics`; Force Dimension's ``libdhd``,
:mod:`.forcedimension`), and the list of known devices (:mod:`.catalog`)."""
