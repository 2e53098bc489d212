"""Workspaces, singular configurations and design studies (sweeps on a Dask cluster)."""
