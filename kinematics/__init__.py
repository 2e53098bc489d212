"""Each paper's kinematic method, one module per method (see the README's paper table)."""
