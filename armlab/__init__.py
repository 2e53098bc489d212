"""armlab: serial robot arms modelled, checked and simulated with Drake.

The subpackages are ``armlab.models`` (the arms and their URDF files),
``armlab.kinematics`` (each paper's method), ``armlab.controllers``,
``armlab.diagrams`` and ``armlab.scripts``. Drake is imported only where needed.
"""

__version__ = "0.1.0"
