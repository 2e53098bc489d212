"""``armlab view`` is reachable only from its own page, and only with its own events (issue 24, item 1).

A real WebSocket client (tornado's) on 127.0.0.1 plays the part of a hostile page: another ``Origin``, another
``Host`` (DNS rebinding), and the frames the battery sent (a NaN or 1e308 slider, a frame that is not msgpack).
Drake's own server must sit on a port browsers refuse, so that the guard cannot be bypassed.
"""

from __future__ import annotations

import asyncio
import io
import math
import urllib.error
import urllib.request

import msgpack
import numpy as np
import pytest
from tornado.httpclient import HTTPClientError, HTTPRequest
from tornado.websocket import websocket_connect

from armlab.models import get_arm
from armlab.presentation.view import Viewer
from armlab.presentation.view_guard import BROWSER_BLOCKED_PORTS, check_event, relayed_event

SLIDERS = {"joint1": (-1.0, 2.0, 0.1)}
BUTTONS = {"Stop viewer"}


def _event(**fields) -> bytes:
    return msgpack.packb(fields)


@pytest.mark.parametrize(("message", "reason"), [
    (b"\xc1garbage", "not msgpack"),
    (b"\x92", "not msgpack"),  # an array of 2 cut short
    ("{\"type\": \"slider\"}", "a text frame"),
    (msgpack.packb([1, 2]), "not an event"),
    (_event(type="slider", name="joint1", value=math.nan), "value nan is outside -1 … 2"),
    (_event(type="slider", name="joint1", value=math.inf), "value inf is outside"),
    (_event(type="slider", name="joint1", value=1e308), "value 1e+308 is outside -1 … 2"),
    (_event(type="slider", name="joint1", value=2.5), "value 2.5 is outside"),
    (_event(type="slider", name="joint1", value=2.06), "value 2.06 is outside -1 … 2"),  # beyond half a step
    (_event(type="slider", name="joint1", value=-1.06), "value -1.06 is outside"),
    (_event(type="slider", name="joint1", value="1"), "value '1' is not a number"),
    (_event(type="slider", name="joint1", value=True), "value True is not a number"),
    (_event(type="slider", name="joint1"), "value None is not a number"),
    (_event(type="slider", name="joint9", value=0.0), "slider 'joint9' is not one of the viewer's"),
    (_event(type="button", name="x" * 1000), "button 'xxx"),
    (_event(type="mouse_drag", name="/drake"), "a 'mouse_drag' event"),
])
def test_check_event_names_what_is_wrong_with_a_message(message, reason):
    found = check_event(message, SLIDERS, BUTTONS)
    assert found is not None and reason in found and len(found) < 120


def test_check_event_passes_the_viewers_own_events():
    assert check_event(_event(type="slider", name="joint1", value=1.5), SLIDERS, BUTTONS) is None
    assert check_event(_event(type="slider", name="joint1", value=-1), SLIDERS, BUTTONS) is None
    assert check_event(_event(type="button", name="Stop viewer"), SLIDERS, BUTTONS) is None


def _page_value(value: float, lowest: float, highest: float, step: float) -> float:
    """What the page's slider (dat.gui) sends for ``value``: clamped to the range, then Math.round(v / step) * step."""
    return math.floor(min(max(value, lowest), highest) / step + 0.5) * step


def test_a_slider_at_its_end_passes_clamped_onto_the_end():
    """At the end of a joint limited to ±π/2 with the viewer's step of 1e-3 rad the page sends ±1.571, beyond the
    limit by its rounding: the guard lets it through, clamped onto the limit, so that the arm reaches it."""
    end, step = math.pi / 2, 1e-3
    sliders = {"joint1": (-end, end, step)}
    for side in (-1, 1):
        sent = _page_value(side * 10.0, -end, end, step)
        assert abs(sent) > end  # the page's own value is beyond the limit
        message = _event(type="slider", name="joint1", value=sent)
        assert check_event(message, sliders, BUTTONS) is None
        relayed = msgpack.unpackb(relayed_event(message, sliders))
        assert relayed == {"type": "slider", "name": "joint1", "value": pytest.approx(side * end, abs=1e-15)}
        assert -end <= relayed["value"] <= end
    inside = _event(type="slider", name="joint1", value=0.25)
    assert relayed_event(inside, sliders) is inside  # within the range: relayed as sent
    assert relayed_event(_event(type="button", name="Stop viewer"), sliders) == _event(type="button",
                                                                                        name="Stop viewer")


@pytest.fixture(scope="module")
def viewer():
    log = io.StringIO()
    viewer = Viewer(get_arm("rr"), np.array([0.5, -0.5]), out=io.StringIO(), log=log)
    viewer.log = log
    yield viewer
    viewer.close()


async def _socket(viewer: Viewer, origin: str, host: str | None = None):
    """A WebSocket to the viewer on 127.0.0.1, as a page at ``origin`` opens it (``host``: its Host header)."""
    headers = {"Origin": origin, "Host": host or f"127.0.0.1:{viewer.guard.port}"}
    return await websocket_connect(HTTPRequest(f"ws://127.0.0.1:{viewer.guard.port}/", headers=headers))


def test_drakes_own_server_is_on_a_port_browsers_refuse(viewer):
    assert viewer.meshcat.port() in BROWSER_BLOCKED_PORTS
    assert viewer.guard.port != viewer.meshcat.port()


@pytest.mark.parametrize("origin", ["http://evil.example", "null", "http://localhost:1", "https://localhost"])
def test_a_websocket_from_another_origin_is_refused(viewer, origin):
    with pytest.raises(HTTPClientError, match="403"):
        asyncio.run(_socket(viewer, origin))
    assert f"refused a WebSocket from origin {origin!r}" in viewer.log.getvalue()


@pytest.mark.parametrize("scheme_host", ["https://127.0.0.1", "ws://127.0.0.1", "wss://localhost", "https://localhost"])
def test_a_websocket_from_the_same_host_with_another_scheme_is_refused(viewer, scheme_host):
    """Issue 36 (also): the viewer's own host and port under another scheme is another origin (tornado's same-host
    rule would pass it); only http://localhost:PORT and http://127.0.0.1:PORT are the page's."""
    origin = f"{scheme_host}:{viewer.guard.port}"
    with pytest.raises(HTTPClientError, match="403"):
        asyncio.run(_socket(viewer, origin))
    assert f"refused a WebSocket from origin {origin!r}" in viewer.log.getvalue()


def test_a_websocket_for_another_host_is_refused(viewer):
    own = f"http://localhost:{viewer.guard.port}"
    with pytest.raises(HTTPClientError, match="403"):
        asyncio.run(_socket(viewer, own, host=f"rebound.example:{viewer.guard.port}"))


def test_pages_are_served_only_for_the_viewers_own_host(viewer):
    for host in (f"localhost:{viewer.guard.port}", f"127.0.0.1:{viewer.guard.port}"):
        request = urllib.request.Request(f"http://127.0.0.1:{viewer.guard.port}/", headers={"Host": host})
        with urllib.request.urlopen(request, timeout=10) as response:
            assert response.status == 200 and b"meshcat" in response.read().lower()
    request = urllib.request.Request(f"http://127.0.0.1:{viewer.guard.port}/",
                                     headers={"Host": f"rebound.example:{viewer.guard.port}"})
    with pytest.raises(urllib.error.HTTPError, match="403"):
        urllib.request.urlopen(request, timeout=10)
    assert "refused a request for Host 'rebound.example:" in viewer.log.getvalue()


def test_hostile_frames_from_the_own_page_are_dropped_and_the_real_slider_moves(viewer):
    hostile = [b"\xc1 not msgpack", _event(type="slider", name="joint1", value=math.nan),
               _event(type="slider", name="joint1", value=1e308), _event(type="gamepad", name="x")]

    async def session() -> tuple[float, bytes | None]:
        connection = await _socket(viewer, f"http://localhost:{viewer.guard.port}")
        scene = await asyncio.wait_for(connection.read_message(), 10)  # Meshcat sends the scene to a new page
        for frame in hostile:
            await connection.write_message(frame, binary=True)
        await connection.write_message(_event(type="slider", name="joint2", value=-1.25), binary=True)
        for _ in range(200):  # the valid event reaches Drake (this thread is Meshcat's main thread)
            if abs(viewer.meshcat.GetSliderValue("joint2") + 1.25) < 1e-12:
                break
            await asyncio.sleep(0.025)
        connection.close()
        return viewer.meshcat.GetSliderValue("joint2"), scene

    viewer.step()  # the first pose: q0 as given
    before = viewer.log.getvalue().count("ignored a message")
    value, scene = asyncio.run(session())
    assert scene is not None
    assert value == pytest.approx(-1.25, abs=1e-12)
    lines = viewer.log.getvalue().splitlines()
    assert viewer.log.getvalue().count("ignored a message") - before == len(hostile)  # one line each
    assert any("not msgpack" in line for line in lines) and any("value nan is outside" in line for line in lines)
    assert viewer.meshcat.GetButtonClicks("Stop viewer") == 0
    assert viewer.step()  # the viewer lives on: its slider moved joint 2
    np.testing.assert_allclose(viewer.q, [0.5, -1.25], atol=1e-3)
    assert np.all(np.isfinite(viewer.tool_position()))


def test_a_slider_sent_to_its_end_by_the_page_reaches_the_end(viewer):
    """Through the guard to Drake: the page's value at the end of a ±π/2 slider (1.571) sets it to π/2."""
    end, step = math.pi / 2, 1e-3
    viewer.meshcat.AddSlider("end test", -end, end, step, 0.0)
    viewer.guard.allow_slider("end test", -end, end, step)

    async def session() -> float:
        connection = await _socket(viewer, f"http://localhost:{viewer.guard.port}")
        await asyncio.wait_for(connection.read_message(), 10)
        await connection.write_message(_event(type="slider", name="end test", value=_page_value(end, -end, end, step)),
                                       binary=True)
        for _ in range(200):
            if abs(viewer.meshcat.GetSliderValue("end test") - end) < 1e-12:
                break
            await asyncio.sleep(0.025)
        connection.close()
        return viewer.meshcat.GetSliderValue("end test")

    try:
        assert asyncio.run(session()) == pytest.approx(end, abs=1e-12)
    finally:
        viewer.meshcat.DeleteSlider("end test")


def test_the_page_opens_its_controls(viewer):
    """Issue 33: the joint sliders hid under Meshcat's "Open Controls" (its viewer closes the panel when it starts);
    the page the viewer serves opens it, after Meshcat's own script made the viewer."""
    from armlab.presentation.view_guard import OPEN_CONTROLS

    request = urllib.request.Request(f"http://127.0.0.1:{viewer.guard.port}/",
                                     headers={"Host": f"localhost:{viewer.guard.port}"})
    with urllib.request.urlopen(request, timeout=10) as response:
        page = response.read()
    assert page.count(OPEN_CONTROLS) == 1 and page.index(b"new MeshCat.Viewer(") < page.index(OPEN_CONTROLS)
    assert page.index(OPEN_CONTROLS) < page.rindex(b"</body>")
