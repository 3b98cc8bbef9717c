"""The FastAPI application: plan from text, N-best lists, structured instructions or speech; places and map.

``create_app({"home": "models/3LDK_06"})`` loads every model, precomputes its planner and draws its map at
start-up (:mod:`spcotmhp.server.registry`); requests pick a model by name (``?model=`` or the body's
``model``), the first one by default. Bad input is a 4xx with a one-line ``detail`` (see :class:`ErrorResponse`):
413 for oversized bodies (:mod:`spcotmhp.server.limits`), 408 for a body that arrives too slowly, 400 for a
Host header naming a host that is not allowed (localhost only by default), 404 for an unknown model, 415 for a
JSON endpoint's body sent with another Content-Type, 422 for invalid fields, an instruction naming no known
place (with the known ``place_words``), a start in a wall or off the map, or audio that is not a usable WAV
file; 409 when no free path reaches the place named; 501 for audio without the speech extra; 503 when the
planner is busy or overloaded (:mod:`spcotmhp.server.overload`) or a plan exceeds the time budget
(:mod:`spcotmhp.server.scheduling`), with ``Retry-After``.
``POST /teach`` learns a place name at run time. ``/docs`` is a self-contained page describing the API from
``/openapi.json`` (no CDN, works offline).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

from fastapi import Depends, FastAPI, File, Form, Query, Request, UploadFile
from fastapi.exceptions import RequestValidationError
from fastapi.responses import FileResponse, JSONResponse, Response
from fastapi.staticfiles import StaticFiles
from starlette.concurrency import run_in_threadpool

from spcotmhp import __version__
from spcotmhp.errors import InstructionError, PlanningError, SpcotmhpError, TeachingError
from spcotmhp.extras import missing_extra
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.server.limits import (
    AUDIO_LIMIT,
    AUDIO_TIMEOUT,
    BODY_TIMEOUT,
    JSON_LIMIT,
    LOCAL_HOSTS,
    BodySizeLimit,
    TrustedHosts,
)
from spcotmhp.server.overload import Admission, OverloadGuard
from spcotmhp.server.registry import ServedModel, load_served
from spcotmhp.server.scheduling import RETRY_AFTER_S, Budget
from spcotmhp.server.schemas import (
    AnyAudioPlanResponse,
    AnyPlanResponse,
    ErrorResponse,
    Health,
    MapInfo,
    ModelsResponse,
    PlacesResponse,
    PlanRequest,
    QuestionsResponse,
    TeachRequest,
    TeachResponse,
)

if TYPE_CHECKING:
    from spcotmhp.building.model import BuildingModel

STATIC = Path(__file__).parent / "static"
ModelQuery = Annotated[str | None, Query(max_length=200, description="Served model name (default: the first).")]
ERROR_CAUSES = {
    400: "The Host header names a host that is not allowed, or the Content-Length header is not a number.",
    404: "No served model has that name.",
    408: "The body did not arrive in time (--body-timeout).",
    409: "No free path reaches a place the instruction names (NoReachablePlace).",
    413: "The body, or the instruction, is too large.",
    415: "A JSON body sent with another Content-Type.",
    422: "An invalid field, an instruction not understood, a start in a wall or off the map.",
    501: "Speech input is not installed (extra 'speech').",
    503: "The planner (or the teaching lane) is busy, the service is overloaded (the requests ahead are expected "
    "to take longer than --max-wait), or the request exceeded its time budget; Retry-After says when to retry.",
}


def errors(*codes: int) -> dict[int | str, dict[str, Any]]:
    """The error answers an endpoint gives, for /openapi.json (each an :class:`ErrorResponse`); 400 for a Host
    header that is not allowed can answer any request."""
    return {code: {"model": ErrorResponse, "description": ERROR_CAUSES[code]} for code in (400, *codes)}


MAP_ERRORS = errors(404, 422)
PLAN_ERRORS = errors(404, 408, 409, 413, 415, 422, 503)
TEACH_ERRORS = errors(404, 408, 413, 415, 422, 503)
AUDIO_ERRORS = errors(404, 408, 409, 413, 422, 501, 503)


class APIError(Exception):
    """An error answer: HTTP status, one-line message and extra JSON fields."""

    def __init__(self, status: int, detail: str, **extra: Any) -> None:
        super().__init__(detail)
        self.status, self.detail, self.extra = status, detail, extra


def create_app(
    models: Mapping[str, str | Path | SpatialConceptModel | BuildingModel],
    *,
    json_limit: int = JSON_LIMIT,
    audio_limit: int = AUDIO_LIMIT,
    progress: Callable[[str], None] | None = None,
    allowed_hosts: Sequence[str] = LOCAL_HOSTS,
    body_timeout: float = BODY_TIMEOUT,
    audio_timeout: float = AUDIO_TIMEOUT,
    budget: Budget | None = None,
) -> FastAPI:
    """The service for ``models`` (name -> model folder or model; the first is the default).

    ``allowed_hosts``: the host names requests may address (``"*"``: any); ``body_timeout`` /
    ``audio_timeout``: seconds to receive a body; ``budget``: planning limits (:class:`Budget`)."""
    served = load_served(models, progress, budget)
    default = next(iter(served))
    app = FastAPI(
        title="spcotmhp",
        version=__version__,
        docs_url=None,
        redoc_url=None,
        description="Hierarchical path planning from spoken or written instructions on learned "
        "topometric semantic maps (SpCoTMHP).",
    )
    app.state.served = served
    limits = budget or Budget()
    _add_guards(app, json_limit, audio_limit, body_timeout, audio_timeout, allowed_hosts, limits)
    _add_error_handlers(app)

    def pick(name: str | None) -> ServedModel:
        key = default if name is None else name
        if key not in served:
            raise APIError(404, f"no model named {key!r}; served: {', '.join(served)}", models=list(served))
        return served[key]

    @app.get("/", include_in_schema=False)
    def index() -> FileResponse:
        return FileResponse(STATIC / "index.html", media_type="text/html")

    @app.get("/docs", include_in_schema=False)
    def docs() -> FileResponse:
        """The API described from /openapi.json by a page of this package (no CDN: works offline)."""
        return FileResponse(STATIC / "docs.html", media_type="text/html")

    app.mount("/static", StaticFiles(directory=STATIC), name="static")

    @app.get("/healthz", response_model=Health, responses=errors(), tags=["service"])
    def healthz() -> dict:
        """Liveness: the service is up and its models are loaded."""
        return {"status": "ok", "models": list(served)}

    @app.get("/models", response_model=ModelsResponse, responses=errors(), tags=["service"])
    def list_models() -> dict:
        """The served models (the default first) with their place words."""
        return {"default": default, "models": [m.summary() for m in served.values()]}

    @app.get("/places", response_model=PlacesResponse, responses=MAP_ERRORS, tags=["map"])
    def places(model: ModelQuery = None) -> dict:
        """The learned places (ids, names, labels, means, covariances, picture colours) and topological edges."""
        return pick(model).places()

    @app.get(
        "/map.png",
        responses={
            200: {"content": {"image/png": {}}},
            304: {"description": "Unchanged (If-None-Match)."},
            **MAP_ERRORS,
        },
        tags=["map"],
        response_class=Response,
    )
    def map_png(
        request: Request,
        model: ModelQuery = None,
        frame: bool = Query(False, description="Axes in metres and a title (not georeferenced)."),
    ):
        """The learned map picture: places as ellipses with names, edges. Without ``frame`` its pixels map
        linearly onto the extent given by ``GET /map.json``. Revalidated on every use (``ETag``; 304 when
        unchanged): a ``POST /teach`` changes it."""
        sm = pick(model)
        headers = {"Cache-Control": "no-cache", "ETag": f'"{sm.name}-{sm.version}-{int(frame)}"'}
        if request.headers.get("if-none-match") == headers["ETag"]:
            return Response(status_code=304, headers=headers)
        png = sm.figure_png() if frame else sm.image.png
        return Response(png, media_type="image/png", headers=headers)

    @app.get("/questions", response_model=QuestionsResponse, responses=MAP_ERRORS, tags=["learning"])
    def questions(
        model: ModelQuery = None, max: int = Query(5, ge=1, le=100, description="Questions to list.")
    ) -> dict:
        """Where an answer ("this is the kitchen") would tell the model most about what a place is called, best
        first (the entropy of the name it expects there); answer one with ``POST /teach`` at its (x, y)."""
        return pick(model).questions(max)

    @app.get("/map.json", response_model=MapInfo, responses=MAP_ERRORS, tags=["map"])
    def map_json(model: ModelQuery = None) -> dict:
        """Georeferencing of ``GET /map.png``: pixel (0, 0) is (x0, y1), pixel (width, height) is (x1, y0)."""
        sm = pick(model)
        return {
            "model": sm.name,
            "image": f"/map.png?model={sm.name}",
            "extent": sm.image.extent,
            "width": sm.image.width,
            "height": sm.image.height,
            "resolution": sm.model.require_map().resolution,
        }

    @app.post("/plan", response_model=AnyPlanResponse, responses=PLAN_ERRORS, tags=["planning"], dependencies=JSON_BODY)
    async def plan(body: PlanRequest, request: Request, response: Response, model: ModelQuery = None) -> dict:
        """Plan from a sentence, an N-best list or a structured instruction, from ``start`` (Algorithm 1).
        503 when the planner is busy, the service is overloaded or the plan exceeds the time budget."""
        sm = pick(_one_model(model, body.model))
        admission = Admission.of(request.scope, limits.max_wait)
        out = await _plan(sm, body.source(), body.start, body.lang, _client(request), body.floor, admission)
        response.headers["Server-Timing"] = admission.timing()
        return out

    @app.post("/teach", response_model=TeachResponse, responses=TEACH_ERRORS, tags=["learning"], dependencies=JSON_BODY)
    async def teach(body: TeachRequest, request: Request, model: ModelQuery = None) -> dict:
        """Teach what a place is called: the name the utterance says at (x, y) is learned at once (online
        learning) and later plans use it; the reply says whether it made a new place or joined one
        (``outcome``, ``message``). 422 for an utterance that names no place ("hello", a question) or a
        position off the map or in a wall (the model is then unchanged); 503 when too many teaches are queued or
        one exceeds the time budget."""
        sm = pick(_one_model(model, body.model))
        try:
            return await sm.teach_async(body.utterance, body.x, body.y, _client(request), body.floor, body.answer)
        except TeachingError as exc:
            raise APIError(exc.http_status, str(exc), cause=type(exc).__name__) from None

    @app.post("/plan/audio", response_model=AnyAudioPlanResponse, responses=AUDIO_ERRORS, tags=["planning"])
    async def plan_audio(
        request: Request,
        response: Response,
        audio: Annotated[UploadFile, File(description="A WAV file (16 kHz mono 16-bit is best).")],
        start: Annotated[str, Form(description='Start pose "x,y" or "[x, y]" in metres.')],
        model: Annotated[str | None, Form(max_length=200)] = None,
        nbest: Annotated[int, Form(ge=1, le=20, description="Hypotheses to keep.")] = 5,
        query_model: Annotated[str | None, Query(alias="model", max_length=200)] = None,
        floor: Annotated[
            str | None, Form(max_length=64, description="A building's model only: the start's floor (index or name).")
        ] = None,
    ) -> dict:
        """Recognise a spoken instruction (pocketsphinx, grammar of the model's place words) and plan from its
        N-best hypotheses (Eq. 25). An error once recognised also lists the ``hypotheses``."""
        sm = pick(_one_model(query_model, model))
        xy = _parse_start(start)
        try:
            from spcotmhp.speech import AudioError, cached_recogniser
        except ImportError:
            raise APIError(501, missing_extra("speech input (pocketsphinx)", "speech")) from None
        data = await audio.read()
        try:
            recogniser = await run_in_threadpool(cached_recogniser, tuple(sm.place_words))
            hypotheses = await run_in_threadpool(recogniser.recognise, data, nbest, audio.filename)
        except AudioError as exc:
            raise APIError(422, str(exc)) from None
        except InstructionError as exc:
            raise APIError(422, str(exc), place_words=sm.place_words) from None
        except SpcotmhpError as exc:
            raise APIError(501, str(exc)) from None
        heard = [{"text": t, "score": s} for t, s in hypotheses]
        admission = Admission.of(request.scope, limits.max_wait)
        try:
            out = await _plan(sm, hypotheses, xy, "en", _client(request), floor, admission)
        except APIError as exc:  # what was heard helps with a plan that failed (an unknown word, a bad start)
            exc.extra["hypotheses"] = heard
            raise
        response.headers["Server-Timing"] = admission.timing()
        return {**out, "hypotheses": heard}

    return app


def _add_guards(
    app: FastAPI,
    json_limit: int,
    audio_limit: int,
    body_timeout: float,
    audio_timeout: float,
    allowed_hosts: Sequence[str],
    budget: Budget,
) -> None:
    """The ASGI middleware, in the order a request meets them: the host check, the overload guard (it sheds before
    a body is read), the body size and time limits."""
    app.add_middleware(
        BodySizeLimit,
        default=json_limit,
        limits={"/plan/audio": audio_limit},
        timeout=body_timeout,
        timeouts={"/plan/audio": audio_timeout},
    )
    app.add_middleware(OverloadGuard, max_wait=budget.max_wait)
    app.add_middleware(TrustedHosts, allowed=allowed_hosts)  # added last: runs first


def require_json(request: Request) -> None:
    """415 for a body sent without a JSON Content-Type (``application/json`` or ``application/*+json``, the
    ones FastAPI reads as JSON): a form or text body would otherwise be a 422 about the body's fields."""
    given = request.headers.get("content-type")
    kind = (given or "").split(";", 1)[0].strip().lower()
    if kind == "application/json" or (kind.startswith("application/") and kind.endswith("+json")):
        return
    sent = "a body without a Content-Type" if given is None else f"Content-Type {given[:80]!r}"
    raise APIError(
        415, f"{sent} is not accepted: {request.url.path} takes a JSON body, sent with Content-Type: application/json"
    )


JSON_BODY = [Depends(require_json)]  # the dependencies of the endpoints that take a JSON body


def _one_model(query: str | None, body: str | None) -> str | None:
    """The model named by the query or the body (the default when neither; an error when they differ)."""
    if query is not None and body is not None and query != body:
        raise APIError(422, f"the query names model {query!r} and the body {body!r}; give one")
    return body if body is not None else query


def _client(request: Request) -> str:
    """The client's address (the unit of fairness on the heavy lane)."""
    return request.client.host if request.client is not None else ""


async def _plan(
    sm: ServedModel,
    source: Any,
    start: Any,
    lang: str | None,
    client: str = "",
    floor: int | str | None = None,
    admission: Admission | None = None,
) -> dict:
    try:
        result = await sm.plan_async(source, start, lang, client, floor, admission)
    except InstructionError as exc:
        raise APIError(exc.http_status, str(exc), place_words=sm.place_words, cause=type(exc).__name__) from None
    except PlanningError as exc:
        raise APIError(exc.http_status, str(exc), cause=type(exc).__name__) from None
    return {"model": sm.name, **result.to_dict()}


def _parse_start(text: str) -> tuple[float, float]:
    import math

    parts = text.strip().strip("[]()").replace(",", " ").split()
    try:
        xy = [float(p) for p in parts]
    except ValueError:
        xy = []
    if len(xy) != 2 or not all(math.isfinite(v) for v in xy):
        raise APIError(422, f'start must be two finite numbers "x,y" in metres, got {text!r}')
    return xy[0], xy[1]


def _add_error_handlers(app: FastAPI) -> None:
    @app.exception_handler(APIError)
    async def api_error(_: Request, exc: APIError) -> JSONResponse:
        headers = {"Retry-After": str(RETRY_AFTER_S)} if exc.status == 503 else None
        return JSONResponse({"detail": exc.detail, **exc.extra}, status_code=exc.status, headers=headers)

    @app.exception_handler(SpcotmhpError)
    async def refused(_: Request, exc: SpcotmhpError) -> JSONResponse:
        """A library error no endpoint turned into an answer (a ModelValueError from inside a teach, say): its
        own 4xx (or 503) with its one-line message, never a 500, since it says what was wrong with the input."""
        return await api_error(_, APIError(exc.http_status, str(exc), cause=type(exc).__name__))

    @app.exception_handler(RequestValidationError)
    async def invalid(_: Request, exc: RequestValidationError) -> JSONResponse:
        errors = [_validation_error(e) for e in exc.errors()]
        detail = "; ".join(f"{e['field']}: {e['msg']}" for e in errors) or "invalid request"
        return JSONResponse({"detail": detail, "errors": errors}, status_code=422)


def _validation_error(e: Mapping[str, Any]) -> dict[str, str]:
    """One pydantic error as {field, msg}: "start/1", "body" (the whole body), "audio" (a form field)."""
    loc = [str(p) for p in e.get("loc", ())]
    msg = str(e.get("msg", "")).removeprefix("Value error, ")
    if e.get("type") == "json_invalid":
        where = f" at character {loc[1]}" if len(loc) > 1 else ""
        return {"field": "body", "msg": f"not valid JSON{where}"}
    return {"field": "/".join(loc[1:]) or (loc[0] if loc else "request"), "msg": msg}
