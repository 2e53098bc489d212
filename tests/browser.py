"""One headless Chromium per test process, driven over the DevTools protocol (``--remote-debugging-pipe``).

Starting Chromium costs about a second of CPU; the replay tests take some twenty screenshots. :func:`screenshot`
opens each page in the one browser, in a browser context of its own (a fresh profile's worth of state: no cache,
no storage shared with another page), and takes its screenshot the way ``chromium --headless
--screenshot --window-size=W,H --virtual-time-budget=B`` does: the page loads, then runs ``B`` ms of virtual time
(which does not advance while a fetch is pending), then the viewport of ``W×H`` CSS pixels is captured as PNG.
The pictures are the same, pixel for pixel, as those of one ``chromium --screenshot`` process per page.
"""

from __future__ import annotations

import atexit
import base64
import fcntl
import json
import os
import select
import shutil
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Any

#: The switches of every launch (as the one-process-per-screenshot command line had them).
SWITCHES = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
            "--disable-background-networking", "--disable-component-update", "--disable-sync"]


class BrowserError(RuntimeError):
    """Chromium ended, answered with an error, or did not answer in time."""


def _above_4(fd: int) -> int:
    """``fd`` moved to a number above 4."""
    moved = fcntl.fcntl(fd, fcntl.F_DUPFD_CLOEXEC, 5)
    os.close(fd)
    return moved


class Browser:
    """A headless Chromium whose DevTools protocol is on a pair of pipes (its fds 3 and 4)."""

    def __init__(self, executable: str) -> None:
        self.profile = tempfile.mkdtemp(prefix="armlab-test-chromium-")
        commands, self._to_chromium = os.pipe()  # Chromium reads fd 3
        self._from_chromium, answers = os.pipe()  # Chromium writes fd 4
        commands, answers = (_above_4(fd) for fd in (commands, answers))  # not themselves 3 or 4 in the child
        shell = f'exec "$0" "$@" 3<&{commands} 4>&{answers} {commands}<&- {answers}>&-'
        self.process = subprocess.Popen(
            ["/bin/bash", "-c", shell, executable, *SWITCHES, f"--user-data-dir={self.profile}",
             "--remote-debugging-pipe", "about:blank"],
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
            pass_fds=(commands, answers))
        os.close(commands)
        os.close(answers)
        self._buffer = b""
        self._id = 0
        self._events: list[dict[str, Any]] = []

    def alive(self) -> bool:
        return self.process.poll() is None

    def _message(self, deadline: float) -> dict[str, Any]:
        while b"\0" not in self._buffer:
            left = deadline - time.monotonic()
            if left <= 0 or not select.select([self._from_chromium], [], [], left)[0]:
                raise BrowserError("chromium did not answer in time")
            chunk = os.read(self._from_chromium, 1 << 20)
            if not chunk:
                raise BrowserError(f"chromium ended (exit code {self.process.poll()})")
            self._buffer += chunk
        message, self._buffer = self._buffer.split(b"\0", 1)
        return json.loads(message)

    def send(self, method: str, params: dict[str, Any] | None = None, session: str | None = None,
             timeout: float = 90) -> dict[str, Any]:
        """The result of the command ``method``; events that arrive meanwhile are kept for :meth:`event`."""
        self._id += 1
        message: dict[str, Any] = {"id": self._id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        try:
            os.write(self._to_chromium, json.dumps(message).encode() + b"\0")
        except OSError as error:
            raise BrowserError(f"chromium ended: {error}") from None
        deadline = time.monotonic() + timeout
        while True:
            answer = self._message(deadline)
            if answer.get("id") == self._id:
                if "error" in answer:
                    raise BrowserError(f"{method}: {answer['error']}")
                return answer.get("result", {})
            self._events.append(answer)

    def event(self, deadline: float) -> dict[str, Any]:
        """The next event (the oldest kept, else the next to arrive)."""
        return self._events.pop(0) if self._events else self._message(deadline)

    def close(self) -> None:
        if self.alive():
            try:
                self.send("Browser.close", timeout=10)
                self.process.wait(timeout=10)
            except (BrowserError, subprocess.TimeoutExpired):
                self.process.kill()
        self.process.wait()
        for fd in (self._to_chromium, self._from_chromium):
            try:
                os.close(fd)
            except OSError:
                pass
        shutil.rmtree(self.profile, ignore_errors=True)


_browser: Browser | None = None


def _the_browser(executable: str) -> Browser:
    global _browser
    if _browser is None or not _browser.alive():
        if _browser is not None:
            _browser.close()
        _browser = Browser(executable)
        atexit.register(_browser.close)
    return _browser


def screenshot(executable: str, pages: list[Path], pngs: list[Path], size: tuple[int, int], budget_ms: int,
               timeout: float = 90) -> None:
    """Each of ``pages`` (files), one after the other, each in a browser context of its own, saved as the PNG at
    the same place in ``pngs`` after ``budget_ms`` of virtual time; :class:`BrowserError` if Chromium fails (and a
    fresh one is started by the next call). One page at a time: pages rendered side by side cost more CPU."""
    global _browser
    browser = _the_browser(executable)
    try:
        for page, png in zip(pages, pngs, strict=True):
            _screenshot(browser, page.absolute().as_uri(), png, size, budget_ms, time.monotonic() + timeout)
    except BrowserError:
        browser.close()
        _browser = None
        raise


def _screenshot(browser: Browser, url: str, png: Path, size: tuple[int, int], budget_ms: int,
                deadline: float) -> None:
    context = browser.send("Target.createBrowserContext", {"disposeOnDetach": True})["browserContextId"]
    target = browser.send("Target.createTarget", {"url": "about:blank", "browserContextId": context})["targetId"]
    session = browser.send("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
    browser.send("Page.enable", session=session)
    browser.send("Emulation.setDeviceMetricsOverride", {"width": size[0], "height": size[1], "deviceScaleFactor": 1,
                                                        "mobile": False}, session=session)
    browser.send("Page.navigate", {"url": url}, session=session)
    running = False
    while True:
        event = browser.event(deadline)
        if event.get("sessionId") != session:
            continue
        method, params = event.get("method"), event.get("params", {})
        if method == "Inspector.targetCrashed":
            raise BrowserError(f"the page {url} crashed")
        if (not running and method == "Page.frameNavigated" and "parentId" not in params["frame"]
                and params["frame"]["url"] == url):
            # The page committed: from now on its clock is virtual, and the budget starts.
            running = True
            browser.send("Emulation.setVirtualTimePolicy", {"policy": "pauseIfNetworkFetchesPending",
                                                            "budget": budget_ms}, session=session)
        elif running and method == "Emulation.virtualTimeBudgetExpired":
            break
    # Capture with the clock running again: with virtual time paused, Chromium 156 never answers a capture of a
    # large static page (the 3 MB report; measured: no answer in 90 s, 4 s with this)
    browser.send("Emulation.setVirtualTimePolicy", {"policy": "advance"}, session=session)
    data = browser.send("Page.captureScreenshot", {"format": "png"}, session=session)["data"]
    png.write_bytes(base64.b64decode(data))
    browser.send("Target.disposeBrowserContext", {"browserContextId": context})  # closes the page too


class Page:
    """A page opened from disk in the test process's Chromium (a browser context of its own), on the real clock,
    with every request it makes recorded (:attr:`requests`); use as a context manager."""

    def __init__(self, executable: str, page: Path, size: tuple[int, int], timeout: float = 90) -> None:
        self.browser = _the_browser(executable)
        self.url = page.absolute().as_uri()
        self.timeout = timeout
        self.requests: list[str] = []
        send = self.browser.send
        self.context = send("Target.createBrowserContext", {"disposeOnDetach": True})["browserContextId"]
        target = send("Target.createTarget", {"url": "about:blank", "browserContextId": self.context})["targetId"]
        self.session = send("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        send("Network.enable", session=self.session)
        send("Emulation.setDeviceMetricsOverride", {"width": size[0], "height": size[1], "deviceScaleFactor": 1,
                                                    "mobile": False}, session=self.session)
        send("Page.navigate", {"url": self.url}, session=self.session)

    def __enter__(self) -> Page:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.browser.send("Target.disposeBrowserContext", {"browserContextId": self.context})

    def _record(self) -> None:
        """Move the requests reported so far into :attr:`requests` (other events are dropped)."""
        for event in list(self.browser._events):
            if event.get("method") == "Network.requestWillBeSent" and event.get("sessionId") == self.session:
                self.requests.append(event["params"]["request"]["url"])
        self.browser._events.clear()

    def evaluate(self, expression: str) -> Any:
        """The value of the JavaScript ``expression`` in the page (awaited if it is a promise; JSON-like)."""
        result = self.browser.send("Runtime.evaluate", {"expression": expression, "returnByValue": True,
                                                        "awaitPromise": True}, session=self.session)
        self._record()
        if "exceptionDetails" in result:
            raise BrowserError(f"{expression[:60]}…: {result['exceptionDetails'].get('text')}")
        return result["result"].get("value")

    def wait_for(self, expression: str) -> Any:
        """Poll ``expression`` every 50 ms until it is truthy (its value), for at most the page's timeout."""
        deadline = time.monotonic() + self.timeout
        while time.monotonic() < deadline:
            value = self.evaluate(f"(() => {{ try {{ return {expression}; }} catch (e) {{ return null; }} }})()")
            if value:
                return value
            time.sleep(0.05)
        raise BrowserError(f"{expression} stayed false for {self.timeout} s")

    def mouse(self, kind: str, x: float, y: float, buttons: int = 1) -> None:
        """A mouse event (``mousePressed``, ``mouseMoved``, ``mouseReleased``) at (x, y) CSS px, left button."""
        self.browser.send("Input.dispatchMouseEvent", {"type": kind, "x": x, "y": y, "button": "left",
                                                       "buttons": buttons, "clickCount": 1}, session=self.session)
        self._record()

    def screenshot(self, png: Path) -> None:
        data = self.browser.send("Page.captureScreenshot", {"format": "png"}, session=self.session)["data"]
        self._record()
        png.write_bytes(base64.b64decode(data))
