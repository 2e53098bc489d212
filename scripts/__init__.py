"""armlab.scripts."""
