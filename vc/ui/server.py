"""The page's side: Starlette (routes, WebSocket, the static page) on uvicorn, in its own thread.

Why Starlette and uvicorn: the page needs one HTML page, its script and one WebSocket, nothing of a
framework's widgets; Starlette is the small, well-kept ASGI toolkit under FastAPI, uvicorn its
reference server, and both run on an event loop of their own in a thread of their own, so the
NC's main thread never waits for the web (see ``vc/ui/bridge.py`` for the hand-overs).  The page is
plain HTML, CSS and JavaScript in ``vc/ui/static`` (in the wheel: it works offline, no CDN).

Security: the server listens on loopback unless told otherwise; bound beyond loopback it asks for
a random token (in the address it prints).  The WebSocket is accepted only from a page of this
server (its Origin), so another web site open in the same browser cannot press keys.  What a page
may do is :class:`vc.ui.panel.Rules`; the answers say why a command was refused.
"""

from __future__ import annotations

import asyncio
import hmac
import ipaddress
import itertools
import json
import os
import secrets
import socket
import tempfile
import threading
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import uvicorn
from starlette.applications import Starlette
from starlette.requests import Request
from starlette.responses import PlainTextResponse, RedirectResponse, Response
from starlette.routing import Mount, Route, WebSocketRoute
from starlette.staticfiles import StaticFiles
from starlette.websockets import WebSocket, WebSocketDisconnect

from vc.scenario.run.trace import write_vcd
from vc.ui.bridge import Command, OperatorBridge

MAX_MESSAGE_CHARACTERS = 65_536  # one command of a page (an MDA program is the longest)
COMMANDS = ("key", "force", "release", "mda", "acknowledge", "handwheel", "watch", "record", "scope")
SCOPE_COPY_TIMEOUT_S = 5.0  # the NC copies the scope's ring between two cycles
STOP_TIMEOUT_S = 5.0


def is_loopback(host: str) -> bool:
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


@dataclass(slots=True)
class _Page:
    """One open page: the latest snapshot not yet sent (coalesced) and the answers to send."""

    wake: asyncio.Event = field(default_factory=asyncio.Event)
    latest: str | None = None
    answers: deque[str] = field(default_factory=deque)


class UiServer:
    """The operator page's web server in its own thread; ``start`` binds (an error comes before the NC runs)."""

    def __init__(self, bridge: OperatorBridge, host: str, port: int, token: str | None = None):
        self.bridge = bridge
        self.host = host
        self.token = token if token is not None else (None if is_loopback(host) else secrets.token_urlsafe(18))
        self._socket = socket.create_server((host, port), family=socket.AF_INET6 if ":" in host else socket.AF_INET)
        self.port = self._socket.getsockname()[1]
        self._pages: dict[int, _Page] = {}
        self._ids = itertools.count(1)
        self._loop: asyncio.AbstractEventLoop | None = None
        self._ready = threading.Event()
        app = Starlette(routes=[
            Route("/", self._index),
            Route("/recording/scenario.yaml", self._scenario),
            Route("/scope.vcd", self._scope_vcd),
            WebSocketRoute("/ws", self._socket_endpoint),
            Mount("/static", app=StaticFiles(packages=[("vc.ui", "static")]), name="static"),
        ])
        self._server = uvicorn.Server(uvicorn.Config(app, log_level="warning", lifespan="off", access_log=False,
                                                     ws="websockets-sansio", ws_max_size=MAX_MESSAGE_CHARACTERS * 4))
        self._thread = threading.Thread(target=self._run, name="vc-ui", daemon=True)
        bridge.publish = self._from_nc(self._publish)
        bridge.announce = self._from_nc(self._publish)

    @property
    def url(self) -> str:
        host = f"[{self.host}]" if ":" in self.host else self.host
        return f"http://{host}:{self.port}/" + (f"?token={self.token}" if self.token else "")

    def start(self) -> None:
        self._thread.start()
        self._ready.wait(STOP_TIMEOUT_S)

    def stop(self) -> None:
        self._server.should_exit = True
        if self._thread.is_alive():
            self._thread.join(STOP_TIMEOUT_S)
        self._socket.close()

    def _run(self) -> None:
        asyncio.run(self._serve())

    async def _serve(self) -> None:
        self._loop = asyncio.get_running_loop()
        self._ready.set()
        await self._server.serve(sockets=[self._socket])

    # ------------------------------------------------------------------ from the NC thread
    def _from_nc(self, handler: Callable[[dict[str, Any]], None]) -> Callable[[dict[str, Any]], None]:
        def hand_over(message: dict[str, Any]) -> None:
            loop = self._loop
            if loop is not None and not loop.is_closed():
                loop.call_soon_threadsafe(handler, message)
        return hand_over

    def _publish(self, message: dict[str, Any]) -> None:
        """In the server's loop: encode once, keep the latest for each page, wake its sender."""
        text = json.dumps(message, separators=(",", ":"))
        for page in self._pages.values():
            if "hello" in message:  # the machine after a power-on: never coalesced away
                page.answers.append(text)
            else:
                page.latest = text
            page.wake.set()

    # ------------------------------------------------------------------ HTTP and WebSocket
    def _token_ok(self, given: str | None) -> bool:
        return self.token is None or (given is not None and hmac.compare_digest(given, self.token))

    async def _index(self, request: Request) -> Response:
        if not self._token_ok(request.query_params.get("token")):
            return PlainTextResponse("this operator panel needs its token: open the address vc serve printed",
                                     status_code=403)
        query = f"?token={self.token}" if self.token else ""
        return RedirectResponse(f"/static/index.html{query}")

    def _scenario(self, request: Request) -> Response:
        """The ended recording as a scenario (a plain function: Starlette runs it in a worker thread,
        so the conversion never holds up the server's loop)."""
        if not self._token_ok(request.query_params.get("token")):
            return PlainTextResponse("this operator panel needs its token", status_code=403)
        download = self.bridge.recording.scenario()
        if download.refusal:
            return PlainTextResponse(download.refusal, status_code=409)
        return Response(download.text, media_type="application/yaml",
                        headers={"Content-Disposition": f'attachment; filename="{download.name}"'})

    def _scope_vcd(self, request: Request) -> Response:
        """The scope's ring as a VCD file, written by the project's trace writer (a plain function:
        run in a worker thread, which waits for the NC to copy the ring between two cycles)."""
        if not self._token_ok(request.query_params.get("token")):
            return PlainTextResponse("this operator panel needs its token", status_code=403)
        copied: list[Any] = []
        done = threading.Event()
        self.bridge.commands.append(Command("scope_copy", 0, "", {"into": copied}, lambda ok, message: done.set()))
        if not done.wait(SCOPE_COPY_TIMEOUT_S) or not copied:
            return PlainTextResponse("the NC ran no cycle to copy the scope in (lockstep waits for the PLC)",
                                     status_code=503)
        recording = copied[0]
        if not recording.histories:
            return PlainTextResponse("the scope has no lanes: pick some on the page", status_code=409)
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "scope.vcd")
            write_vcd(recording, path)
            with open(path, encoding="utf-8") as handle:
                text = handle.read()
        return Response(text, media_type="text/x-vcd",
                        headers={"Content-Disposition": 'attachment; filename="scope.vcd"'})

    def _same_origin(self, websocket: WebSocket) -> bool:
        origin = websocket.headers.get("origin")
        host = websocket.headers.get("host")
        return origin is None or (host is not None and origin in (f"http://{host}", f"https://{host}"))

    async def _socket_endpoint(self, websocket: WebSocket) -> None:
        if not self._token_ok(websocket.query_params.get("token")) or not self._same_origin(websocket):
            await websocket.close(code=1008)  # policy violation
            return
        await websocket.accept()
        number = next(self._ids)
        page = _Page()
        self._pages[number] = page
        self.bridge.pages += 1
        peer = websocket.client.host if websocket.client is not None else ""
        description = self.bridge.description
        if description is not None:
            page.latest = json.dumps(description)
            page.wake.set()
        sender = asyncio.create_task(self._send(websocket, page))
        try:
            while True:
                text = await websocket.receive_text()
                self._take(number, peer, page, text)
        except WebSocketDisconnect:
            pass
        finally:
            sender.cancel()
            del self._pages[number]
            self.bridge.pages -= 1
            self.bridge.commands.append(Command("closed", number, peer))

    async def _send(self, websocket: WebSocket, page: _Page) -> None:
        while True:
            await page.wake.wait()
            page.wake.clear()
            while page.answers:
                await websocket.send_text(page.answers.popleft())
            text, page.latest = page.latest, None
            if text is not None:
                await websocket.send_text(text)

    def _take(self, number: int, peer: str, page: _Page, text: str) -> None:
        """A page's command: checked for its shape here, for what it asks by the NC thread (the bridge)."""
        loop = self._loop
        assert loop is not None
        reference: object = None

        def answer(done: bool, message: str) -> None:  # called in the NC thread
            reply = json.dumps({"reply": reference, "done": done, "message": message})

            def queue() -> None:
                page.answers.append(reply)
                page.wake.set()
            if not loop.is_closed():
                loop.call_soon_threadsafe(queue)

        try:
            if len(text) > MAX_MESSAGE_CHARACTERS:
                raise ValueError(f"a command of more than {MAX_MESSAGE_CHARACTERS} characters")
            message = json.loads(text)
            if not isinstance(message, dict):
                raise ValueError("a command is a JSON object")
            reference = message.get("id")
            kind = message.get("command")
            if kind not in COMMANDS:
                raise ValueError(f"unknown command {kind!r} (known: {', '.join(COMMANDS)})")
            arguments = message.get("arguments", {})
            if not isinstance(arguments, dict):
                raise ValueError("the arguments of a command are a JSON object")
            if kind == "scope" and not (isinstance(arguments.get("names"), list)
                                        and all(isinstance(name, str) for name in arguments["names"])
                                        and isinstance(arguments.get("seconds"), (int, float))):
                raise ValueError("scope takes a list of names and the seconds to keep")
            if kind == "watch" and not (isinstance(arguments.get("names"), list)
                                        and all(isinstance(name, str) for name in arguments["names"])):
                raise ValueError("watch takes a list of names")
        except ValueError as error:  # json.JSONDecodeError too
            page.answers.append(json.dumps({"reply": reference, "done": False, "message": f"refused: {error}"}))
            page.wake.set()
            return
        self.bridge.commands.append(Command(kind, number, peer, arguments, answer))
