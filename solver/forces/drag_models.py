"""The cheap force approximations of the paper's section 3.1.

* aerodynamic drag ``F = -C_AD rho |v| v A`` (eq. 5), for low viscosity;
* viscous (Stokes) drag ``F = -C_VD mu v A`` (eq. 6), for slow or very viscous flow.

``v`` is the probe's velocity relative to the fluid (the fluid is usually taken at rest), ``A`` the
projected cross-section (2D: a length, giving N/m). Neither gives a torque.
"""

from __future__ import annotations

import numpy as np


def quadratic_drag(
    relative_velocity_m_s: np.ndarray, density_kg_m3: float, area: float, coefficient: float = 1.0
) -> np.ndarray:
    """Aerodynamic drag (paper eq. 5) opposing ``relative_velocity_m_s``."""
    v = np.asarray(relative_velocity_m_s, dtype=float)
    return -coefficient * density_kg_m3 * float(np.linalg.norm(v)) * v * area


def viscous_drag(
    relative_velocity_m_s: np.ndarray,
    dynamic_viscosity_pa_s: float,
    area: float,
    coefficient: float = 1.0,
) -> np.ndarray:
    """Viscous drag (paper eq. 6) opposing ``relative_velocity_m_s``; linear in velocity."""
    v = np.asarray(relative_velocity_m_s, dtype=float)
    return -coefficient * dynamic_viscosity_pa_s * v * area
