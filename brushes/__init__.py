"""Brush tips: signed-distance geometry, presets, stylus-to-tip mapping, paint reservoir."""
