"""Benchmark: the replay of paper 000's 15 s rrrr run with its graphs — its file size and how fast a seek is.

``armlab simulate rrrr``'s run (1 ms log samples) is written as ``replay.html`` (goal: ≤ 5 MB) and opened from disk
in headless Chromium (tests/browser.py, the real clock, a 1000 × 800 window). In the page, a seek is what a click
on a graph does — pause, seek the 3-D animation, move the slider, the readout and every graph's cursor — followed
by drawing the 3-D view once (``viewer.render()``, waited for by reading a pixel back), as the next frame would;
it is timed with
``performance.now()`` at ``--seeks`` run times spread over the run (goal: ≤ 50 ms each). The reference measured
in the same page is one draw of the 3-D view alone; the ratio says what a seek costs over a frame. The page's own
share of a seek (everything but the draw, with the layout it causes) is printed too: headless Chromium draws WebGL
in software (SwiftShader), so the draw, not the seek, sets the time — which is why the replay makes its context
without multisampling on a software renderer and clears to white instead of drawing Meshcat's background texture
(:data:`armlab.presentation.replay.SOFTWARE_GL`; a draw 101 → 21 ms here).

Run: ``.venv/bin/python scripts/bench/bench_replay.py`` (or ``make bench``).
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import sys
import tempfile
from pathlib import Path

from armlab.diagrams.simulate import simulate
from armlab.models import get_arm
from armlab.planning.motions import paper_motion
from armlab.presentation.replay import replay_log

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from browser import Page  # type: ignore[import-not-found]  # the tests' Chromium driver (tests/ is no package)

#: Goals of issue 23: the file (bytes) and a seek (ms).
SIZE_GOAL, SEEK_GOAL = 5_000_000, 50.0
#: In-page timing: every seek (then a draw), and draws alone, in turns; milliseconds.
TIMING = """(() => {
  const times = %s, seek = [], draw = [], gl = viewer.renderer.getContext(), pixel = new Uint8Array(4);
  const drawn = () => { viewer.render(); gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel); };
  const page = [];
  for (const t of times) {
    let start = performance.now(); armlab.seek(t); void document.body.offsetHeight;
    page.push(performance.now() - start);
    drawn();
    start = performance.now(); armlab.seek(t); drawn(); seek.push(performance.now() - start);
    start = performance.now(); drawn(); draw.push(performance.now() - start);
  }
  return {page, seek, draw};
})()"""


def main(argv: list[str] | None = None) -> int:
    """Print the replay's size and the seeks' median and worst time against one draw of the 3-D view."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeks", type=int, default=40, help="seeks timed (default 40)")
    args = parser.parse_args(argv)
    chromium = next((p for p in map(shutil.which, ("chromium", "chromium-browser", "google-chrome")) if p), None)
    if chromium is None:
        raise SystemExit("bench_replay needs headless Chromium (apt-get install -y chromium)")
    arm = get_arm("rrrr")
    log = simulate(arm, paper_motion(arm))
    with tempfile.TemporaryDirectory() as folder:
        path = replay_log(log, Path(folder) / "replay.html")
        size = path.stat().st_size
        times = [15.0 * (k + 0.5) / args.seeks for k in range(args.seeks)]
        with Page(chromium, path, (1000, 800)) as page:
            page.wait_for("window.armlab && viewer.animator.playing")  # loaded and playing, as on opening
            page.evaluate(TIMING % times)  # warm-up: the first draws compile the shaders
            measured = page.evaluate(TIMING % times)
    page_ms, seek, draw = measured["page"], measured["seek"], measured["draw"]
    print(f"rrrr, paper 000's 15 s run ({log.t.size} log samples): replay.html {size / 1e6:.2f} MB "
          f"(goal ≤ {SIZE_GOAL / 1e6:g} MB)")
    print(f"  seek + draw: median {statistics.median(seek):.1f} ms, worst {max(seek):.1f} ms of {len(seek)} "
          f"(goal ≤ {SEEK_GOAL:g} ms)")
    print(f"  draw alone:  median {statistics.median(draw):.1f} ms; seek / draw = "
          f"{statistics.median(seek) / statistics.median(draw):.2f}×")
    print(f"  the page's own work of a seek (animation, slider, readout, cursors, layout; no draw): median "
          f"{statistics.median(page_ms):.2f} ms, worst {max(page_ms):.2f} ms")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
