"""Numerics for incompressible viscous flow on a staggered MAC grid (2D and 3D).

Knows nothing of brushes, rendering or devices.
"""
