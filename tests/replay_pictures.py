"""What a replay page shows in headless Chromium: screenshots at chosen playback times, the 3-D view's pixels,
and the check that a replay shows the arm, large, moving (used by test_replay.py and test_reproduce.py)."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest
from browser import BrowserError, screenshot
from matplotlib.image import imread

from armlab.presentation.replay import BAR_HEIGHT
from armlab.presentation.replay_graphs import GRAPHS_PCT

WINDOW = (1000, 800)
#: Seek the replay's animation to a playback time once the page has loaded it (test-only script).
SEEK_SCRIPT = """<script>
(function armlabSeek() {{
  const animator = viewer.animator;
  if (animator.actions.length === 0) {{ setTimeout(armlabSeek, 10); return; }}
  animator.pause(); animator.seek({time}); viewer.set_dirty();
}})();
</script>
"""


def chromium() -> str:
    for name in ("chromium", "chromium-browser", "google-chrome"):
        if path := shutil.which(name):
            return path
    pytest.fail("headless Chromium is needed to check the replay: apt-get install -y chromium (make test does it)")


def screenshots(html: Path, times: tuple[float, ...], tmp: Path) -> list[Path]:
    """Screenshots of ``html`` opened from disk, with playback sought to each of ``times`` (the pages at once).

    Each page is what ``chromium --headless --screenshot --window-size=1000,800 --virtual-time-budget=3000`` shows,
    taken by this test process's one Chromium (tests/browser.py: a browser context per page instead of a
    Chromium started per page; the same pixels, a second of CPU less per page)."""
    text = html.read_text()
    end = text.rfind("</body>")
    pages, pngs = [], []
    for k, t in enumerate(times):
        page = tmp / f"{html.stem}-at-{k}.html"
        page.write_text(text[:end] + SEEK_SCRIPT.format(time=repr(float(t))) + text[end:] if end >= 0 else text)
        pages.append(page)
        pngs.append(tmp / f"{html.stem}-at-{k}.png")
    try:
        screenshot(chromium(), pages, pngs, WINDOW, budget_ms=3000, timeout=90)
    except BrowserError as error:
        raise AssertionError(f"chromium failed to screenshot {html.name}: {error}") from error
    for png in pngs:
        assert png.exists(), f"chromium wrote no {png.name}"
    return pngs


def image(png: Path) -> np.ndarray:
    """RGB in 0 … 1 of the 3-D view: below Meshcat's "Open Controls" bar (the top 24 rows are cropped), above the
    replay's control bar (its :data:`BAR_HEIGHT` rows, whose readout changes with time) and left of the graphs
    (:data:`GRAPHS_PCT` % of the width, whose cursors move with time)."""
    rgb = imread(png)[24:-BAR_HEIGHT, :, :3]
    return rgb[:, : rgb.shape[1] * (100 - GRAPHS_PCT) // 100]


def solid(mask: np.ndarray) -> np.ndarray:
    """``mask`` eroded twice (3×3): one- or two-pixel lines — the tool path, anti-aliasing — vanish,
    bodies drawn several pixels thick remain."""
    for _ in range(2):
        inner = np.zeros_like(mask)
        inner[1:-1, 1:-1] = np.logical_and.reduce(
            [mask[1 + i : mask.shape[0] - 1 + i, 1 + j : mask.shape[1] - 1 + j] for i in (-1, 0, 1) for j in (-1, 0, 1)]
        )
        mask = inner
    return mask


def assert_shows_arm_moving(png_a: Path, png_b: Path) -> None:
    """Both screenshots show the arm, large, on the replay's white background, and the arm is in
    a different pose in each."""
    for png in (png_a, png_b):
        drawn = np.abs(image(png) - 1.0).max(axis=-1) > 0.1
        assert drawn.mean() < 0.7, f"{png.name}: {drawn.mean():.0%} of the image is not the replay's white background"
        bodies = solid(drawn)
        assert bodies.mean() > 0.004, f"{png.name}: only {bodies.mean():.2%} of the image shows solid bodies drawn"
        rows, cols = np.nonzero(bodies)
        extent = max(np.ptp(cols) / bodies.shape[1], np.ptp(rows) / bodies.shape[0])
        assert extent > 0.2, f"{png.name}: the arm spans only {extent:.0%} of the view"
    # In the arm's region (the bounding box of the solid bodies drawn at either time), the bodies moved:
    # pixels that show a body at one time and not at the other.
    bodies_a, bodies_b = (solid(np.abs(image(png) - 1.0).max(axis=-1) > 0.1) for png in (png_a, png_b))
    rows, cols = np.nonzero(bodies_a | bodies_b)
    region = (slice(rows.min(), rows.max() + 1), slice(cols.min(), cols.max() + 1))
    changed = solid(np.abs(image(png_a) - image(png_b)).max(axis=-1) > 0.1)[region]
    moved = changed.sum() / bodies_a.size
    assert moved > 0.002, f"the two playback times look the same ({moved:.3%} of the image differs in the arm's region)"
    assert (bodies_a ^ bodies_b)[region].sum() > 0.5 * changed.sum(), "what changed is not where the arm is drawn"
