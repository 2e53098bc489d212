"""An arm's drive train per joint (gear ratio, rotor inertia, efficiency, friction, the motors' electrics), read from
drive files and DH columns, and its Coulomb friction as a Drake system.
May import: base, kinematics.
"""
