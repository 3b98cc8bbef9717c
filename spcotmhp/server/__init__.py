"""The HTTP service (extra ``server``: FastAPI + uvicorn): ``spcotmhp serve MODEL_DIR`` or

    >>> from spcotmhp.server import create_app
    >>> app = create_app({"home": "demo-output/model"})        # then: uvicorn.run(app)

Endpoints: ``POST /plan``, ``POST /plan/audio``, ``GET /places``, ``GET /map.png``, ``GET /map.json``,
``GET /models``, ``GET /healthz``, the web page at ``/`` and the OpenAPI schema at ``/openapi.json``
(modules: ``app`` routes and errors, ``schemas`` bodies, ``registry`` served models, ``scheduling`` lanes,
admission and the time budget, ``limits`` body sizes, body timeouts and trusted hosts, ``static/`` the page and
the offline API description at ``/docs``).
"""

from __future__ import annotations

from typing import Any

from spcotmhp.extras import missing_extra


def create_app(*args: Any, **kwargs: Any) -> Any:
    """:func:`spcotmhp.server.app.create_app` (imported on use, so that the package needs no FastAPI)."""
    try:
        from spcotmhp.server.app import create_app as factory
    except ModuleNotFoundError as exc:
        if exc.name in ("fastapi", "starlette", "pydantic", "multipart", "python_multipart"):
            from spcotmhp.errors import SpcotmhpError

            raise SpcotmhpError(missing_extra(f"the HTTP service (module {exc.name})", "server")) from None
        raise
    return factory(*args, **kwargs)


__all__ = ["create_app"]
