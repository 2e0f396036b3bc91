"""What every layer shares and nothing heavy: user-input errors (:mod:`.errors`), strict TOML
tables (:mod:`.tables`), the name rules for files' identifiers (:mod:`.names`), orientation math
(quaternions, :mod:`.quaternion`; the stylus tilt convention, :mod:`.tilt`), the wall time of a
step's phases (:mod:`.timing`), command-line output to a pipe that may close early
(:mod:`.pipes`), and the size, memory and nesting limits every file reader checks first
(:mod:`.limits`).

Imports only the standard library and numpy, so the servo loop can start light.
"""
