"""The page's web server (vc/ui/server.py) on 127.0.0.1, an ephemeral port and time-outs: the token,
the same-origin rule for the WebSocket, the static page from the package, malformed commands refused."""

from __future__ import annotations

import asyncio
import json
import time
import urllib.error
import urllib.request
from collections.abc import Iterator

import pytest
import websockets
from websockets.exceptions import InvalidStatus

from vc.ui.bridge import OperatorBridge
from vc.ui.server import UiServer, is_loopback

TIMEOUT_S = 10.0


@pytest.fixture
def server() -> Iterator[UiServer]:
    served = UiServer(OperatorBridge(), "127.0.0.1", 0, token="s3cret")
    served.start()
    try:
        yield served
    finally:
        served.stop()


def get(url: str) -> tuple[int, str]:
    try:
        with urllib.request.urlopen(url, timeout=TIMEOUT_S) as response:
            return response.status, response.read().decode()
    except urllib.error.HTTPError as error:
        return error.code, error.read().decode()


def test_loopback_needs_no_token_beyond_it_one_is_made() -> None:
    assert is_loopback("127.0.0.1") and is_loopback("localhost") and is_loopback("::1")
    assert not is_loopback("0.0.0.0") and not is_loopback("192.168.1.10")
    served = UiServer(OperatorBridge(), "127.0.0.1", 0)
    try:
        assert served.token is None and served.url == f"http://127.0.0.1:{served.port}/"
    finally:
        served.stop()


def test_the_page_and_its_assets_come_from_the_package_with_the_token(server: UiServer) -> None:
    base = f"http://127.0.0.1:{server.port}"
    status, text = get(f"{base}/")
    assert status == 403 and "token" in text
    status, text = get(f"{base}/?token=wrong")
    assert status == 403
    status, text = get(server.url)  # redirected to the page
    assert status == 200 and "<title>VC operator panel</title>" in text
    assert "http" not in text.replace(base, "")  # nothing from another host: it works offline
    status, script = get(f"{base}/static/panel.js")
    assert status == 200 and "new WebSocket" in script


def exchange(server: UiServer, messages: list[str], token: str | None = "s3cret", origin: str | None = None,
             expect: int = 0) -> list[dict[str, object]]:
    async def talk() -> list[dict[str, object]]:
        query = f"?token={token}" if token else ""
        async with websockets.connect(f"ws://127.0.0.1:{server.port}/ws{query}", origin=origin,  # type: ignore[arg-type]
                                      open_timeout=TIMEOUT_S) as socket:
            for message in messages:
                await socket.send(message)
            return [json.loads(await asyncio.wait_for(socket.recv(), TIMEOUT_S)) for _ in range(expect)]
    return asyncio.run(talk())


def test_the_websocket_wants_the_token_and_the_pages_origin(server: UiServer) -> None:
    with pytest.raises(InvalidStatus):
        exchange(server, [], token=None)
    with pytest.raises(InvalidStatus):
        exchange(server, [], origin="http://evil.example")
    assert exchange(server, [], origin=f"http://127.0.0.1:{server.port}") == []


def test_malformed_commands_are_answered_not_fatal(server: UiServer) -> None:
    answers = exchange(server, ["not json", "[1]", json.dumps({"id": 7, "command": "explode"}),
                                json.dumps({"id": 8, "command": "watch", "arguments": {"names": "X1"}}),
                                "x" * 70_000], expect=5)
    assert [answer["done"] for answer in answers] == [False] * 5
    assert "unknown command 'explode'" in str(answers[2]["message"]) and answers[2]["reply"] == 7
    assert "list of names" in str(answers[3]["message"])
    assert "more than" in str(answers[4]["message"])
    # the server still runs: a good command is queued for the NC thread, and the closed page is told
    exchange(server, [json.dumps({"id": 9, "command": "acknowledge"})])
    end = time.monotonic() + TIMEOUT_S
    while time.monotonic() < end and "closed" not in [command.kind for command in server.bridge.commands][-1:]:
        time.sleep(0.05)
    kinds = [command.kind for command in server.bridge.commands]
    assert kinds[-2:] == ["acknowledge", "closed"], kinds
    assert "explode" not in kinds and "watch" not in kinds


def test_the_downloads_want_the_token_and_say_why_there_is_nothing(server: UiServer) -> None:
    """No NC cycles here: the VCD cannot be copied (503, said why); no --record: no scenario (409)."""
    base = f"http://127.0.0.1:{server.port}"
    for path in ("/scope.vcd", "/recording/scenario.yaml"):
        assert get(f"{base}{path}")[0] == 403
    status, text = get(f"{base}/recording/scenario.yaml?token=s3cret")
    assert status == 409 and "--record FILE" in text
    status, text = get(f"{base}/scope.vcd?token=s3cret")
    assert status == 503 and "no cycle" in text
    answers = exchange(server, [json.dumps({"id": 3, "command": "scope", "arguments": {"names": ["X1.position"]}}),
                                json.dumps({"id": 4, "command": "scope_copy", "arguments": {}})], expect=2)
    assert "seconds to keep" in str(answers[0]["message"])
    assert "unknown command 'scope_copy'" in str(answers[1]["message"])  # the server's own, never a page's
