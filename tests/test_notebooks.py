"""The notebooks run: each is executed headless in a fresh Jupyter kernel (nbclient), fails on any error, and
every cell that shows a figure produced an image. Their outputs are never committed."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))


def test_there_are_notebooks_and_none_holds_outputs():
    assert len(NOTEBOOKS) >= 4
    for path in NOTEBOOKS:
        cells = json.loads(path.read_text())["cells"]
        for cell in cells:
            if cell["cell_type"] == "code":
                assert cell["outputs"] == [] and cell["execution_count"] is None, f"{path.name} holds outputs"


@pytest.mark.slow
@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_runs(path, tmp_path, monkeypatch, capfd):
    import nbformat
    from jupyter_client.manager import KernelManager
    from nbclient import NotebookClient

    monkeypatch.chdir(tmp_path)  # a notebook writes nothing into the repository
    notebook = nbformat.read(path, as_version=4)
    # over IPC, as docs/conf.py runs them: no TCP port, no warning of an unencrypted one
    kernel = KernelManager(kernel_name="python3", transport="ipc")
    NotebookClient(notebook, km=kernel, timeout=600, resources={"metadata": {"path": str(tmp_path)}}
                   ).execute()  # raises CellExecutionError, naming the cell, on any error
    assert "without encryption" not in capfd.readouterr().err
    figures = 0
    for cell in notebook.cells:
        if cell.cell_type != "code":
            continue
        images = [o for o in cell.outputs if "image/png" in o.get("data", {})]
        if "plt.show()" in cell.source:
            assert images, f"{path.name}: a figure cell showed no image:\n{cell.source[:200]}"
        figures += len(images)
        if cell.source.strip() in ("run", "arm") or cell.source.startswith("arm  #"):  # Run, Arm shown by Jupyter
            html = [o["data"]["text/html"] for o in cell.outputs if "text/html" in o.get("data", {})]
            assert html and ("<iframe" in html[0] if cell.source.strip() == "run" else "<table" in html[0]), path.name
        assert not [o for o in cell.outputs if o.get("output_type") == "error"]
    assert figures >= 1


def test_the_workspace_notebook_prints_the_volume_it_labels(capsys, monkeypatch):
    """Issue 33: notebook 04 printed "volume reach 1.0043 m" (the measure's name as a label, then the reach); its
    first cell now prints the volume it names, with its unit, and the reach — the numbers of its own ``ws``."""
    import matplotlib

    matplotlib.use("Agg")
    monkeypatch.setattr("matplotlib.pyplot.show", lambda *a, **k: None)
    notebook = json.loads((ROOT / "notebooks" / "04_workspace_and_study.ipynb").read_text())
    cell = next(c for c in notebook["cells"] if c.get("id") == "04-01")
    space: dict = {}
    exec("".join(cell["source"]), space)  # the notebook's own cell, as its kernel runs it
    ws = space["ws"]
    line = capsys.readouterr().out.strip()
    assert line == f"volume {ws.volume:.4g} m³, reach {ws.reach:.4f} m", line
    assert ws.measure == "volume" and ws.volume_unit == "m³"
