"""Tables of the library arms computed for models/README.md (``python -m armlab.papers.library_tables``).

:func:`puma560_gravity` — the Puma 560's gravity torques (N·m, the torques that hold it still) at the Robotics
Toolbox's named configurations qz, qr, qs, qn (:data:`armlab.models.library.puma560.CONFIGURATIONS`), by armlab's
inverse dynamics; :func:`puma560_gravity_table` prints them as the README's markdown table. tests/test_library.py
checks the README's table against them (and the toolbox's ``gravload``, where it is installed).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from armlab.models import get_arm
from armlab.models.library.puma560 import CONFIGURATIONS

__all__ = ["puma560_gravity", "puma560_gravity_table"]


def puma560_gravity() -> dict[str, NDArray[np.float64]]:
    """τ_g (6,) N·m of the Puma 560 at rest at each named configuration, gravity (0, 0, −9.81) m/s²."""
    arm = get_arm("puma560")
    zero = np.zeros(arm.n)
    return {name: arm.inverse_dynamics(np.array(q, dtype=float), zero, zero) for name, q in CONFIGURATIONS.items()}


def puma560_gravity_table() -> str:
    """The markdown table of :func:`puma560_gravity`, 4 decimals (−0 printed as 0)."""
    lines = ["| configuration | q (deg) | τ1 | τ2 | τ3 | τ4 | τ5 | τ6 |", "| --- | --- |" + " ---: |" * 6]
    for name, tau in puma560_gravity().items():
        q = ", ".join(f"{v:g}" for v in np.degrees(CONFIGURATIONS[name]))
        values = " | ".join(f"{v + 0.0:.4f}" for v in np.round(tau, 4))
        lines.append(f"| `{name}` | ({q}) | {values} |")
    return "\n".join(lines)


if __name__ == "__main__":
    print(puma560_gravity_table())
