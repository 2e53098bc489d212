"""armlab.diagrams."""
