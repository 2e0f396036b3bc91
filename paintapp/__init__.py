"""The haptic fluid painting application, one subpackage per stage.

:mod:`.canvas` the canvas and its files; :mod:`.pigments` colour; :mod:`.strokes` stroke files;
:mod:`.paint` the local paint grid and paint transfer; :mod:`.session` samples -> brush -> grid
-> canvas, forces out, replays; :mod:`.haptics` the servo loop and the device drivers;
:mod:`.render` moderngl rendering; :mod:`.app` the Qt window; :mod:`.explore` feeling a stored
flow; :mod:`.bench` cost against accuracy; :mod:`.figures` and :mod:`.commands` the
sub-commands of :mod:`.cli`, the command line. At the root: :mod:`.resources` (the shipped data),
:mod:`.atomic` (atomic writes of user files) and :mod:`.output_paths` (a command's output paths,
checked before any work).
"""

__version__ = "0.1.0"
