"""Writing a workspace into its folder (``armlab workspace --out DIR``): completely or not at all.

:func:`workspace_folder` is an :class:`~armlab.files.OutputFolder` made before the workspace is sampled (so an
unwritable place is an error up front) and renamed onto the requested folder only when every file is written;
an earlier workspace folder there is replaced, any other non-empty folder is left alone (an error).
:func:`write_workspace` writes the files into it.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING

from armlab.files import OutputFolder

if TYPE_CHECKING:
    from armlab.analysis.workspace import Workspace
    from armlab.models.arm import Arm

__all__ = ["WORKSPACE_FILES", "workspace_folder", "write_workspace"]

#: What ``armlab workspace --out DIR`` writes (a folder holding only these may be replaced).
WORKSPACE_FILES = ("workspace.json", "slices.png", "convergence.png", "singular.png", "collisions.png",
                   "workspace.html")


def workspace_folder(out: str | Path) -> OutputFolder:
    """The output folder of a workspace (:class:`~armlab.files.OutputFolder`)."""

    def is_previous(folder: Path) -> bool:
        names = {p.name for p in folder.iterdir()}
        return "workspace.json" in names and names <= set(WORKSPACE_FILES)

    return OutputFolder(Path(out).expanduser(), is_previous, "an armlab workspace folder (workspace.json and its "
                                                            "pictures only)")


def write_workspace(arm: Arm, ws: Workspace, folder: Path) -> list[str]:
    """:data:`WORKSPACE_FILES` of ``arm``'s workspace ``ws`` into ``folder``: ``workspace.json`` (its summary), the
    pictures (:func:`~armlab.analysis.plots.workspace_figures`) and ``workspace.html`` (the 3-D point cloud,
    :func:`~armlab.analysis.cloud.write_point_cloud`); the names written."""
    # lazy: armlab --help loads armlab.analysis.output but not this (start-up time)
    from armlab.analysis.cloud import write_point_cloud
    from armlab.analysis.plots import workspace_figures

    (folder / "workspace.json").write_text(json.dumps(ws.summary(), indent=2, ensure_ascii=False) + "\n")
    written = ["workspace.json", *workspace_figures(ws, folder)]
    write_point_cloud(arm, ws, folder / "workspace.html")
    return [*written, "workspace.html"]
