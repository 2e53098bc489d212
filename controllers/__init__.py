"""armlab.controllers."""
