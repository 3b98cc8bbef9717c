"""Bounded request bodies: an ASGI middleware that answers 413 before the application sees an oversized body.

The body is read here (at most ``limit`` bytes; a larger declared Content-Length is refused without reading)
and replayed to the application, so the limit holds for chunked uploads as well as declared ones.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from typing import Any

JSON_LIMIT = 64 * 1024
AUDIO_LIMIT = 5 * 1024 * 1024


class BodySizeLimit:
    """ASGI middleware: request bodies above ``limits[path]`` (else ``default``) bytes get 413."""

    def __init__(self, app: Any, default: int = JSON_LIMIT, limits: Mapping[str, int] | None = None) -> None:
        self.app = app
        self.default = default
        self.limits = dict(limits or {})

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
        while True:
            message = await receive()
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
    await send({"type": "http.response.start", "status": status,
                "headers": [(b"content-type", b"application/json"), (b"content-length", str(len(body)).encode()),
                            (b"connection", b"close")]})
    await send({"type": "http.response.body", "body": body})
