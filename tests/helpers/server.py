"""Helpers shared by the service tests (importable, no pytest fixtures): model folders of the bundled homes
(supervised fits, fast and deterministic), a start pose, free ports and a `spcotmhp serve` process."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path
from typing import Self

import httpx
import numpy as np

from spcotmhp.datasets import load_bundled
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.persistence.io import save_model
from tests.helpers.graphs import GRAPHS

INSTRUCTION = "go to the bedroom via the corridor"


def supervised_model_dir(home: str, folder: Path, lang: str = "en") -> Path:
    """The supervised fit of a bundled home (its ``lang`` words), saved to ``folder``."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        data = load_bundled(home, lang=lang)
    return save_model(fit_supervised(data), folder)


def start_near(model, place: str = "entrance") -> list[float]:
    """The demo's start: the free cell nearest the place's mean."""
    from spcotmhp.commands.demo import demo_start
    from spcotmhp.planning.planner import HierarchicalPlanner

    xy, _ = demo_start(HierarchicalPlanner(model, cache=GRAPHS), place)
    return [float(v) for v in xy]


def wall_point(model) -> list[float]:
    """A map-frame point in an occupied cell."""
    rows, cols = np.nonzero(model.map.occupied)
    return [float(v) for v in model.map.cell_to_world(np.array([rows[len(rows) // 2], cols[len(cols) // 2]]))]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


class ServerProcess:
    """``spcotmhp serve ARGS --port P`` in a subprocess, ready when /healthz answers; a context manager."""

    def __init__(self, args: list[str], timeout: float = 120.0) -> None:
        self.args, self.timeout = args, timeout
        self.port = free_port()
        self.url = f"http://127.0.0.1:{self.port}"
        self.proc: subprocess.Popen | None = None
        # the server's output goes to a file, not a pipe: an unread pipe blocks a server that writes 64 KiB
        fd, name = tempfile.mkstemp(prefix="spcotmhp-serve-", suffix=".log")
        os.close(fd)
        self.log = Path(name)

    def output_tail(self, lines: int = 40) -> str:
        """The last ``lines`` lines the server wrote (stdout and stderr), for failure messages."""
        try:
            text = self.log.read_text(encoding="utf-8", errors="replace")
        except OSError as exc:
            return f"(no server output: {exc})"
        return "\n".join(text.splitlines()[-lines:]) or "(the server wrote nothing)"

    def __enter__(self) -> Self:
        cmd = [
            sys.executable,
            "-m",
            "spcotmhp.cli",
            "serve",
            *self.args,
            "--port",
            str(self.port),
            "--log-level",
            "warning",
        ]
        with self.log.open("ab") as out:  # appended to, however the file is read meanwhile
            self.proc = subprocess.Popen(
                cmd, stdout=out, stderr=subprocess.STDOUT, env={**os.environ, "PYTHONUNBUFFERED": "1"}
            )
        deadline = time.monotonic() + self.timeout
        while time.monotonic() < deadline:
            if self.proc.poll() is not None:
                message = f"spcotmhp serve exited with {self.proc.returncode}:\n{self.output_tail()}"
                self.log.unlink(missing_ok=True)
                raise RuntimeError(message)
            try:
                if httpx.get(self.url + "/healthz", timeout=1.0).status_code == 200:
                    return self
            except httpx.HTTPError:
                pass
            time.sleep(0.2)
        message = f"spcotmhp serve did not answer on {self.url} within {self.timeout} s:\n{self.output_tail()}"
        self.__exit__()
        raise RuntimeError(message)

    def __exit__(self, *exc: object) -> None:
        if self.proc is not None and self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        self.log.unlink(missing_ok=True)


def farthest_spot(model) -> np.ndarray:
    """The free cell centre (x, y) of ``model``'s map farthest, by the Mahalanobis distance of each active place's
    Gaussian, from its nearest place: where a teach is apart from every place."""
    occ = model.require_map()
    xy = occ.cell_to_world(np.argwhere(occ.free))
    far = np.full(len(xy), np.inf)
    for k in np.flatnonzero(model.active_places):
        d = xy - model.mu[k]
        far = np.minimum(far, np.einsum("ni,ij,nj->n", d, np.linalg.inv(model.Sigma[k]), d))
    return xy[int(np.argmax(far))]
