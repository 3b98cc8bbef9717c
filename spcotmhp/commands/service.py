"""CLI command of the service area: ``spcotmhp serve MODEL_DIR [NAME=MODEL_DIR ...] [--host] [--port]``."""

from __future__ import annotations

import contextlib
import errno
import math
import re
import socket
from enum import StrEnum
from pathlib import Path
from typing import Annotated

import typer

from spcotmhp.collector import end_startup
from spcotmhp.commands import body_options as bo
from spcotmhp.errors import ModelError, SpcotmhpError
from spcotmhp.extras import missing_extra

DEFAULT_PORT = 8000  # `serve --port`'s default; the demo's hint names another when this one is taken


class LogLevel(StrEnum):
    """uvicorn's log levels (a bad value is a usage error listing them)."""

    critical = "critical"
    error = "error"
    warning = "warning"
    info = "info"
    debug = "debug"
    trace = "trace"


def model_mapping(items: list[str]) -> dict[str, Path]:
    """``["a/3LDK_06", "home=b/model"]`` -> {"3LDK_06": a/3LDK_06, "home": b/model}: a model is named by
    ``NAME=`` or by its folder's name; names must be unique."""
    out: dict[str, Path] = {}
    for item in items:
        match = re.fullmatch(r"([A-Za-z0-9_.-]+)=(.+)", item)
        name, folder = (match.group(1), Path(match.group(2))) if match else (None, Path(item))
        if name is None:
            name = re.sub(r"[^A-Za-z0-9_.-]", "_", folder.resolve().name)[:64] or "model"
        if name in out:
            raise ModelError(f"two models are named {name!r} ({out[name]} and {folder}); name them with NAME=MODEL_DIR")
        out[name] = folder
    return out


def listening_socket(host: str, port: int) -> socket.socket:
    """A TCP socket bound to ``host``:``port`` (as uvicorn binds it: IPv6 when the host has a colon,
    SO_REUSEADDR), for the server to listen on; an address in use or not available is a one-line
    :class:`SpcotmhpError` before anything says the service is up."""
    sock = socket.socket(family=socket.AF_INET6 if ":" in host else socket.AF_INET)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        sock.bind((host, port))
    except OSError as exc:  # socket.gaierror (an unknown host name) included
        sock.close()
        where = f"[{host}]:{port}" if ":" in host else f"{host}:{port}"
        if exc.errno == errno.EADDRINUSE:
            raise SpcotmhpError(
                f"cannot listen on {where}: the port is already in use; stop what holds it or choose another "
                "--port (--port 0: any free port)"
            ) from None
        reason = exc.strerror or str(exc)
        raise SpcotmhpError(f"cannot listen on {where}: {reason}; check --host and --port") from None
    sock.set_inheritable(True)
    return sock


def _in_seconds(value: float, low: float) -> float:
    """A finite number of seconds in [low, 600], else a usage error naming the range."""
    if not (math.isfinite(value) and low <= value <= 600):
        raise typer.BadParameter(f"must be a finite number of seconds in [{low:g}, 600], got {value:g}")
    return value


def _seconds(value: float) -> float:
    """A --time-budget or --body-timeout: seconds in [0.1, 600]."""
    return _in_seconds(value, 0.1)


def _wait_seconds(value: float) -> float:
    """A --max-wait: seconds in [0.001, 600] (a millisecond: about one light plan)."""
    return _in_seconds(value, 0.001)


# long: a CLI command: 40 lines of typer options and help, a 33-line body
def serve(
    models: Annotated[
        list[str],
        typer.Argument(
            help="Model folders (as written by `spcotmhp learn`), each optionally NAME=FOLDER; the first is the "
            "default.",
            metavar="MODEL_DIR...",
        ),
    ],
    host: Annotated[str, typer.Option(help="Interface to listen on (default: this machine only).")] = "127.0.0.1",
    port: Annotated[int, typer.Option(min=0, max=65535, help="TCP port (0: any free port).")] = DEFAULT_PORT,
    log_level: Annotated[LogLevel, typer.Option(help="uvicorn log level.")] = LogLevel.info,
    allowed_host: Annotated[
        list[str] | None,
        typer.Option(
            "--allowed-host",
            help="A host name clients may address (Host header), repeatable; default localhost, "
            "127.0.0.1 and ::1 (plus --host when it is a specific address); '*' allows any.",
        ),
    ] = None,
    time_budget: Annotated[
        float,
        typer.Option(callback=_seconds, help="Seconds (0.1 to 600) a request may wait for its plan before a 503."),
    ] = 5.0,
    body_timeout: Annotated[
        float, typer.Option(callback=_seconds, help="Seconds (0.1 to 600) to receive a JSON request body before a 408.")
    ] = 10.0,
    nav2_params: bo.Nav2Params = None,
    robot_radius: bo.RobotRadius = None,
    footprint: bo.Footprint = None,
    inflation_radius: bo.InflationRadius = None,
    cost_scaling_factor: bo.CostScaling = None,
    max_wait: Annotated[
        float,
        typer.Option(
            callback=_wait_seconds,
            help="Seconds (0.001 to 600) the plans ahead of a request may be expected to take; past that it is "
            "refused at once with 503 and Retry-After (docs/speed.md, 'Under overload').",
        ),
    ] = 1.0,
) -> None:
    """Serve planning over HTTP (FastAPI): POST /plan, /plan/audio and /teach; GET /places, /questions, /map.png,
    /map.json, /models and /healthz; the web page at /.

    Requests must address an allowed host (DNS-rebinding protection); long instructions run on a second
    planner per model with admission limits, so they cannot starve short ones; the API description at /docs
    works offline."""
    from rich.console import Console

    from spcotmhp.server import create_app
    from spcotmhp.server.limits import LOCAL_HOSTS
    from spcotmhp.server.scheduling import Budget

    try:
        import uvicorn
    except ImportError:
        raise SpcotmhpError(missing_extra("serving (uvicorn)", "server")) from None
    from spcotmhp.building.io import is_building_model, load_building_model
    from spcotmhp.persistence.io import load_model

    console = Console(stderr=True, soft_wrap=True)  # lines whole: scripts read the address from them
    from spcotmhp.planning.body import with_body

    mapping = model_mapping(models)
    body = bo.body_from_options(nav2_params, robot_radius, footprint, inflation_radius, cost_scaling_factor)
    with console.status("loading models"):
        loaded = {  # a bad model is named first; a building's model is served with its building planner
            name: load_building_model(folder, body)
            if is_building_model(folder)
            else with_body(load_model(folder), body)
            for name, folder in mapping.items()
        }
    sock = listening_socket(host, port)  # before the planners are precomputed: a port in use fails at once
    hosts = list(allowed_host or LOCAL_HOSTS)
    if not allowed_host and host not in LOCAL_HOSTS + ("0.0.0.0", "::"):
        hosts.append(host)
    with console.status("precomputing planners") as status:
        app = create_app(
            loaded,
            progress=lambda name: status.update(f"precomputing the planner of model {name!r}"),
            allowed_hosts=hosts,
            body_timeout=body_timeout,
            budget=Budget(time_budget=time_budget, max_wait=max_wait),
        )
    for name, folder in mapping.items():
        graph = app.state.served[name].planner.graph
        console.print(f"model {name!r}: {folder} (planning graph {graph.info.get('graph_source', 'built')})")
    if host not in LOCAL_HOSTS:
        console.print(
            f"[yellow]warning: listening on {host}, reachable from other machines; the service has no "
            "authentication[/yellow]"
        )
        console.print(f"allowed hosts (Host header): {', '.join(hosts)}; add names with --allowed-host NAME")
    shown = f"[{host}]" if ":" in host else host
    port = sock.getsockname()[1]  # the port chosen when --port 0
    console.print(f"serving {len(mapping)} model(s) on http://{shown}:{port}/ (API docs: /docs, schema: /openapi.json)")
    end_startup()
    server = uvicorn.Server(uvicorn.Config(app, host=host, port=port, log_level=LogLevel(log_level).value))
    with contextlib.suppress(KeyboardInterrupt):  # Ctrl-C stops the service quietly, as uvicorn.run does
        server.run(sockets=[sock])
    if not server.started:
        raise SpcotmhpError("the service did not start (uvicorn's message above says why)")


def register(app: typer.Typer) -> None:
    """Add the service commands to ``app``."""
    app.command()(serve)
