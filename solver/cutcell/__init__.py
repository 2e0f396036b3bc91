"""The default boundary: cut cells from the probes' signed distances (Batty, Bertails & Bridson
2007).

Open face fractions and fluid volumes (:mod:`.geometry`), implicit viscosity with no-slip at the
true surface (:mod:`.viscosity`), the face-weighted pressure projection (:mod:`.projection`) and
the stress integral over the cut surface (:mod:`.forces`).
"""
