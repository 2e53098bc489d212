"""Each paper's kinematic method, one module per method (see the README's paper table), and the batched
kinematics and dynamics (forward, Jacobians, IK, RNEA, quintics, tool paths) they share.
May import: base.
"""
