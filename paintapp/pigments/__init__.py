"""Colour: the pigment library (:mod:`.library`), Kubelka-Munk two-flux theory
(:mod:`.kubelka_munk`), spectra and colourimetry (:mod:`.spectra`), the renderer's band tables
and the CPU reference colour (:mod:`.bands`), and the upsampling cache (:mod:`.spectrum_cache`)."""
