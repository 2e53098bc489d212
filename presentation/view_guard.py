"""The guard in front of ``armlab view``'s Meshcat: only the viewer's own page reaches it, and only with sane events.

Drake's Meshcat server (uWebSockets) accepts a WebSocket from any ``Origin`` and a page request with any ``Host``,
and it takes every event a client sends: a slider at 1e308 or NaN, the "Stop viewer" button, and a frame that is
not msgpack aborts the process (only ``msgpack::type_error`` is caught). So any web page open in the user's
browser could drive or kill the viewer (and, through DNS rebinding, read it). The viewer therefore never exposes
Drake's server:

* Drake's server listens on a loopback port that browsers refuse to connect to, one of the Fetch standard's
  "bad ports" (https://fetch.spec.whatwg.org/#port-blocking: ``fetch`` and ``WebSocket`` to them fail in every
  browser), so no page can reach it directly;
* the port the viewer prints is this guard (tornado), which serves Drake's pages only for a ``Host`` of
  ``localhost:PORT`` or ``127.0.0.1:PORT`` (HTTP 403 otherwise), accepts a WebSocket only from the page's own
  origin, ``http://localhost:PORT`` or ``http://127.0.0.1:PORT`` (403 otherwise), and relays to Drake only the
  events the viewer uses, checked: a click of one of its buttons, a finite value of one of its sliders within
  that slider's range. Anything else (not msgpack, another event type, an unknown name, a non-finite or
  out-of-range value) is dropped with one log line. The page's slider (dat.gui) rounds its value to the step
  after clamping it to the range, ``Math.round(value / step) * step``, so at an end that is not a whole number
  of steps it sends up to half a step beyond it (±π/2 with a step of 1e-3: ±1.571): such a value is relayed
  clamped onto the end (:func:`relayed_event`), so that the slider reaches its joint's limit.
"""

from __future__ import annotations

import asyncio
import gc
import math
import sys
import threading
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, TextIO

import msgpack
from tornado.httpclient import AsyncHTTPClient
from tornado.httpserver import HTTPServer
from tornado.ioloop import IOLoop
from tornado.netutil import bind_sockets
from tornado.web import Application
from tornado.websocket import WebSocketClosedError, WebSocketHandler, websocket_connect

from armlab.presentation.replay import start_meshcat
from armlab.values import shown

if TYPE_CHECKING:
    import socket

    from pydrake.geometry import Meshcat

__all__ = ["BROWSER_BLOCKED_PORTS", "MAX_MESSAGE", "OPEN_CONTROLS", "Guard", "check_event", "open_controls",
           "relayed_event", "start_hidden_meshcat"]

#: The Fetch standard's "bad ports" above 1023 (no browser connects to them), in the order tried for Drake's
#: own server; 6000 (X11) last.
BROWSER_BLOCKED_PORTS = (6665, 6666, 6667, 6668, 6669, 6679, 6697, 10080, 4190, 6566, 3659, 5060, 5061, 1719,
                         1720, 1723, 2049, 4045, 6000)
#: Largest WebSocket message the guard accepts from a page (bytes); the viewer's events are under 100 bytes.
MAX_MESSAGE = 4096


def start_hidden_meshcat() -> Meshcat:
    """Drake's Meshcat on localhost, on the first free one of :data:`BROWSER_BLOCKED_PORTS`.

    Raises ``ValueError`` when all of them are in use.
    """
    for port in BROWSER_BLOCKED_PORTS:
        try:
            return start_meshcat(port)
        except RuntimeError:
            continue
    raise ValueError(f"no free port among {BROWSER_BLOCKED_PORTS} for the viewer's Meshcat; stop another viewer")


#: A slider: its (lowest, highest, step) value, in the slider's own units.
SliderRange = tuple[float, float, float]


#: What the viewer's page runs after Meshcat's own script: its control panel (the joint sliders) open, not folded
#: under "Open Controls" (Meshcat's viewer closes it when it starts).
OPEN_CONTROLS = b"<script>viewer.gui.open();</script>"


def open_controls(page: bytes) -> bytes:
    """Meshcat's page with :data:`OPEN_CONTROLS` before its ``</body>``; any other response unchanged."""
    end = page.rfind(b"</body>")
    if b"new MeshCat.Viewer(" not in page or end < 0:
        return page
    return page[:end] + OPEN_CONTROLS + page[end:]


def _beyond(step: float) -> float:
    """How far beyond an end a slider of ``step`` may send: half a step (its rounding), and the rounding's float
    error (``Math.round(e / step) * step`` is a product, not the exact multiple)."""
    return 0.5 * step * (1 + 1e-9)


def check_event(message: bytes | str, sliders: Mapping[str, SliderRange], buttons: set[str]) -> str | None:
    """Why a page's WebSocket ``message`` must not reach Meshcat, or None when it is one of the viewer's events.

    ``sliders``: name → (lowest, highest, step) value of each slider (a value up to half a step beyond an end is
    the page's rounding, allowed: :func:`relayed_event` clamps it); ``buttons``: the names of the buttons.
    """
    if isinstance(message, str):
        return "a text frame (Meshcat's events are binary msgpack)"
    try:
        event = msgpack.unpackb(message, raw=False)
    except (ValueError, TypeError, msgpack.UnpackException) as error:  # ExtraData, FormatError, StackError …
        return f"not msgpack ({type(error).__name__})"
    if not isinstance(event, dict) or not isinstance(event.get("type"), str) or not isinstance(event.get("name"),
                                                                                                 str):
        return f"not an event with a type and a name: {shown(event)}"
    kind, name = event["type"], event["name"]
    if kind == "button":
        return None if name in buttons else f"button {shown(name)} is not one of the viewer's"
    if kind != "slider":
        return f"a {shown(kind)} event (the viewer uses only its sliders and buttons)"
    if name not in sliders:
        return f"slider {shown(name)} is not one of the viewer's"
    value = event.get("value")
    if isinstance(value, bool) or not isinstance(value, int | float):
        return f"slider {name}: value {shown(value)} is not a number"
    lowest, highest, step = sliders[name]
    if not math.isfinite(value) or not lowest - _beyond(step) <= value <= highest + _beyond(step):  # not a bound: input
        return f"slider {name}: value {shown(value)} is outside {lowest:g} … {highest:g}"
    return None


def relayed_event(message: bytes, sliders: Mapping[str, SliderRange]) -> bytes:
    """The ``message`` that passed :func:`check_event` as it goes to Meshcat: a slider's value beyond an end (the
    page's rounding to the step) re-encoded clamped onto that end; any other message unchanged."""
    event = msgpack.unpackb(message, raw=False)
    if event["type"] != "slider":
        return message
    lowest, highest, _step = sliders[event["name"]]
    if lowest <= event["value"] <= highest:  # not a bound: a page's event (its own rounding allowed above)
        return message
    return msgpack.packb({**event, "value": min(max(float(event["value"]), lowest), highest)})


class Guard:
    """The viewer's public server on ``localhost:port``, relaying the viewer's own page to Drake's ``meshcat``.

    Binds at once (``OSError`` when the port is in use; ``port=0``: any free one) and serves from a thread of
    its own until :meth:`close`. Register the sliders and buttons a page may use with :meth:`allow_slider` and
    :meth:`allow_button`; each dropped event or refused connection writes one line to ``log``.
    """

    def __init__(self, meshcat: Meshcat, port: int, log: TextIO = sys.stderr) -> None:
        # Only Meshcat's port is kept: a Drake object must never be freed in the guard's thread (its destructor
        # aborts off the main thread), and a garbage collection there could free one that a cycle holds.
        self._upstream = f"127.0.0.1:{meshcat.port()}"
        self._sockets: list[socket.socket] = bind_sockets(port, address="localhost")
        self.port: int = self._sockets[0].getsockname()[1]
        self.sliders: dict[str, SliderRange] = {}
        self.buttons: set[str] = set()
        self.log = log
        self.hosts = {f"localhost:{self.port}", f"127.0.0.1:{self.port}"}
        self.origins = {f"http://{host}" for host in self.hosts}
        self._loop: IOLoop | None = None
        gc.collect()  # here, in the main thread: no garbage of earlier Drake objects for the guard's thread
        started = threading.Event()
        self._thread = threading.Thread(target=self._serve, args=(started,), name="armlab-view-guard", daemon=True)
        self._thread.start()
        started.wait()

    @property
    def url(self) -> str:
        """The page's address, ``http://localhost:PORT``."""
        return f"http://localhost:{self.port}"

    def allow_slider(self, name: str, lowest: float, highest: float, step: float) -> None:
        """Let the page set slider ``name`` to values in ``lowest`` … ``highest`` in steps of ``step`` (> 0; the
        slider's own units: an end's value rounded to the step arrives clamped onto the end)."""
        if not step > 0:
            raise ValueError(f"slider {name}: step = {step} must be > 0")
        self.sliders = {**self.sliders, name: (float(lowest), float(highest), float(step))}

    def allow_button(self, name: str) -> None:
        """Let the page click button ``name``."""
        self.buttons = self.buttons | {name}

    def note(self, text: str) -> None:
        """One log line."""
        print(f"armlab view: {text}", file=self.log, flush=True)

    def _serve(self, started: threading.Event) -> None:
        asyncio.set_event_loop(asyncio.new_event_loop())
        self._loop = IOLoop.current()
        app = Application([(r"/.*", _Relay, {"guard": self})], websocket_max_message_size=MAX_MESSAGE,
                          log_function=lambda _handler: None)  # refusals are logged once, by _Relay
        server = HTTPServer(app)
        server.add_sockets(self._sockets)
        self._loop.add_callback(started.set)
        self._loop.start()
        server.stop()
        self._loop.close(all_fds=True)

    def close(self) -> None:
        """Stop serving (the page loses its connection)."""
        if self._loop is not None and self._thread.is_alive():
            self._loop.add_callback(self._loop.stop)
            self._thread.join(timeout=10)


class _Relay(WebSocketHandler):
    """One request to the guard: a page or file (GET, fetched from Drake's server) or the page's WebSocket."""

    guard: Guard
    upstream: Any = None

    def initialize(self, guard: Guard) -> None:  # tornado's per-request set-up
        self.guard = guard

    def prepare(self) -> None:  # before any handling: the Host check (DNS rebinding) and a WebSocket's Origin
        host = self.request.headers.get("Host", "")
        if host not in self.guard.hosts:
            self.guard.note(f"refused a request for Host {shown(host)} (only {' or '.join(sorted(self.guard.hosts))})")
            self.send_error(403)
            return
        # Tornado skips check_origin for an Origin whose host and port are the Host's whatever its scheme
        # (https://…, ws://…) and for a "Sec-Fetch-Site: same-origin" header: the page's own origin is checked here.
        origin = self.request.headers.get("Origin")
        if (self.request.headers.get("Upgrade", "").lower() == "websocket" and origin is not None
                and not self.check_origin(origin)):
            self.send_error(403)

    def check_origin(self, origin: str) -> bool:
        if origin in self.guard.origins:
            return True
        self.guard.note(f"refused a WebSocket from origin {shown(origin)} (only the viewer's own page)")
        return False

    async def get(self, *args: Any, **kwargs: Any) -> None:
        if self.request.headers.get("Upgrade", "").lower() == "websocket":
            await super().get(*args, **kwargs)
            return
        response = await AsyncHTTPClient().fetch(f"http://{self.guard._upstream}{self.request.uri}",
                                                 raise_error=False)
        self.set_status(response.code)
        if "Content-Type" in response.headers:
            self.set_header("Content-Type", response.headers["Content-Type"])
        self.finish(open_controls(response.body or b""))

    async def open(self, *args: Any, **kwargs: Any) -> None:
        self.upstream = await websocket_connect(f"ws://{self.guard._upstream}/")
        IOLoop.current().add_callback(self._from_meshcat)

    async def _from_meshcat(self) -> None:
        while (message := await self.upstream.read_message()) is not None:
            try:
                await self.write_message(message, binary=isinstance(message, bytes))
            except WebSocketClosedError:
                break
        self.close()

    async def on_message(self, message: bytes | str) -> None:
        sliders = self.guard.sliders
        reason = check_event(message, sliders, self.guard.buttons)
        if reason is not None:
            self.guard.note(f"ignored a message from the page: {reason}")
            return
        assert isinstance(message, bytes), "check_event refuses a text frame"
        await self.upstream.write_message(relayed_event(message, sliders), binary=True)

    def on_close(self) -> None:
        if self.upstream is not None:
            self.upstream.close()
