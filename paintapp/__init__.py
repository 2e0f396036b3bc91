"""The haptic fluid painting application: canvas, pigments, haptics, rendering, files, CLI."""

__version__ = "0.1.0"
