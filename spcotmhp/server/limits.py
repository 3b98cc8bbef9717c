"""Request guards as ASGI middleware, answering before the application sees a request:

* :class:`BodySizeLimit`: bodies over ``limit`` bytes get 413 (a larger declared Content-Length is refused
  without reading; the body is read here and replayed, so the limit holds for chunked uploads too), and a body
  that has not fully arrived ``timeout`` seconds after the request started gets 408 (a client trickling
  2 bytes a second cannot hold a connection and a buffer forever).
* :class:`TrustedHosts`: a request whose ``Host`` header names a host outside ``allowed`` gets 400 (a web page
  on another site that rebinds its DNS name to 127.0.0.1 cannot reach the service). ``LOCAL_HOSTS`` by
  default; ``"*"`` allows any host.
"""

from __future__ import annotations

import asyncio
import json
import time
from collections.abc import Iterable, Mapping
from typing import Any

JSON_LIMIT = 64 * 1024
AUDIO_LIMIT = 5 * 1024 * 1024
BODY_TIMEOUT = 10.0  # seconds to receive a JSON body
AUDIO_TIMEOUT = 60.0  # seconds to receive an audio upload
LOCAL_HOSTS = ("localhost", "127.0.0.1", "::1")


class TrustedHosts:
    """ASGI middleware: HTTP requests must name an allowed host (port ignored) in their Host header."""

    def __init__(self, app: Any, allowed: Iterable[str] = LOCAL_HOSTS) -> None:
        self.app = app
        self.allowed = {h.lower().strip("[]") for h in allowed}

    async def __call__(self, scope: dict, receive: Any, send: Any) -> None:
        if scope["type"] != "http" or "*" in self.allowed:
            await self.app(scope, receive, send)
            return
        raw = dict(scope.get("headers") or ()).get(b"host", b"").decode("latin-1").strip().lower()
        if host_name(raw) not in self.allowed:
            shown = raw[:60] or "(none)"
            await _answer(
                send,
                400,
                f"host {shown!r} is not served; allowed hosts: {', '.join(sorted(self.allowed))}"
                " (spcotmhp serve --allowed-host NAME adds one)",
            )
            return
        await self.app(scope, receive, send)


def host_name(header: str) -> str:
    """The host of a Host header without its port: "localhost:8000" -> localhost, "[::1]:80" -> ::1."""
    if header.startswith("["):
        return header[1:].split("]", 1)[0]
    return header.rsplit(":", 1)[0] if header.count(":") == 1 else header


class BodySizeLimit:
    """ASGI middleware: request bodies above ``limits[path]`` (else ``default``) bytes get 413."""

    def __init__(
        self,
        app: Any,
        default: int = JSON_LIMIT,
        limits: Mapping[str, int] | None = None,
        timeout: float = BODY_TIMEOUT,
        timeouts: Mapping[str, float] | None = None,
    ) -> None:
        self.app = app
        self.default = default
        self.limits = dict(limits or {})
        self.timeout = timeout
        self.timeouts = dict(timeouts or {})

    async def __call__(self, scope: dict, receive: Any, send: Any) -> None:
        if scope["type"] != "http" or scope["method"] in ("GET", "HEAD", "OPTIONS"):
            await self.app(scope, receive, send)
            return
        limit = self.limits.get(scope["path"], self.default)
        headers = dict(scope.get("headers") or ())
        declared = headers.get(b"content-length")
        if declared is not None:
            try:
                size = int(declared)
            except ValueError:
                await _answer(send, 400, f"bad Content-Length header {declared.decode('latin-1')!r}")
                return
            if size > limit:
                await _answer(send, 413, _too_large(scope["path"], size, limit))
                return
        chunks, size = [], 0
        allowed = self.timeouts.get(scope["path"], self.timeout)
        deadline = time.monotonic() + allowed
        while True:
            try:
                message = await asyncio.wait_for(receive(), max(deadline - time.monotonic(), 0.0))
            except TimeoutError:
                await _answer(
                    send,
                    408,
                    f"request body for {scope['path']} not received within {allowed:g} s ({size} bytes arrived)",
                )
                return
            if message["type"] == "http.disconnect":
                return
            chunk = message.get("body", b"")
            size += len(chunk)
            if size > limit:
                await _answer(send, 413, _too_large(scope["path"], None, limit))
                return
            chunks.append(chunk)
            if not message.get("more_body", False):
                break
        body = b"".join(chunks)
        replayed = False

        async def replay() -> dict:
            nonlocal replayed
            if not replayed:
                replayed = True
                return {"type": "http.request", "body": body, "more_body": False}
            return await receive()

        await self.app(scope, replay, send)


def _too_large(path: str, size: int | None, limit: int) -> str:
    got = f"{size} bytes" if size is not None else "more"
    return f"request body too large for {path}: {got} (limit {limit} bytes)"


async def _answer(send: Any, status: int, detail: str) -> None:
    body = json.dumps({"detail": detail}).encode()
    await send(
        {
            "type": "http.response.start",
            "status": status,
            "headers": [
                (b"content-type", b"application/json"),
                (b"content-length", str(len(body)).encode()),
                (b"connection", b"close"),
            ],
        }
    )
    await send({"type": "http.response.body", "body": body})
