"""Flows computed elsewhere: pressure and velocity sampled on a regular grid (:mod:`.flow`), the
force they exert on a probe placed in them (:mod:`.forces`) and quadrature rules on a probe's
exact surface (:mod:`.quadrature`).
"""
