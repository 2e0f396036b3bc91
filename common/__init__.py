"""What every layer shares and nothing heavy: user-input errors, strict TOML tables, the name
rules for files' identifiers, and orientation math (quaternions, the stylus tilt convention).

Imports only the standard library and numpy, so the servo loop can start light.
"""
