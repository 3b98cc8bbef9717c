"""Issue 26 from the outside: every case of the issue, and hostile variants of them, run as a user runs them
(the ``spcotmhp`` command, or a short library script in a fresh interpreter) and judged by what the user sees.

Each case builds its inputs under a root folder (model folders whose values were changed behind a resealed
manifest, sparse files of gigabytes, PGM/PNG headers, a map split by a closed door, a busy port) and runs one
command. The outcome is judged by :func:`judge`: the exit status is the expected one (0, or 2 for a refusal),
a refusal prints exactly one ``error:`` line naming what the case expects and nothing else on stderr, and no
output holds a traceback. ``tests/test_hostile_cases.py`` runs them as tests;
``python -m tests.helpers.hostile_cases [ROOT] [NAME ...]`` prints a table with each case's exit status and
wall time (the acceptance of issue 26 asks for < 3 s each on a quiet machine).

A library case (``lib:NAME``) runs :func:`library_case` in a fresh interpreter: it prints ``ok: ...`` and exits
0, or, on a library error (:class:`~spcotmhp.errors.SpcotmhpError`), prints ``error: ...`` and exits 2, as the
command line does; anything else escapes as a traceback (exit 1).
"""

from __future__ import annotations

import json
import os
import re
import shutil
import signal
import socket
import struct
import subprocess
import sys
import time
import warnings
import zlib
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
EXE = str(Path(sys.executable).with_name("spcotmhp"))
GIB = 1 << 30
SPARSE = 8 * GIB


@dataclass
class Case:
    """One hostile input: ``build(root)`` writes it and returns the command (argv after ``spcotmhp``, or
    ``["lib:NAME", ...]``); the answer must exit with ``status`` and (a refusal) say ``expect`` (a regex)."""

    name: str
    item: str  # the item it belongs to, or "variant"
    build: Callable[[Path], list[str]]
    status: int = 2
    expect: str = ""
    slow: bool = False  # more than a few seconds to build or run: left out of the quick test run
    env: dict = field(default_factory=dict)


@dataclass
class Outcome:
    status: int
    seconds: float
    stdout: str
    stderr: str

    @property
    def error_lines(self) -> list[str]:
        return [line for line in self.stderr.splitlines() if line.strip()]


# ---- templates ----------------------------------------------------------------------------------------------
def template_model(root: Path) -> Path:
    """A supervised model of a generated four-room flat (seed 1), saved once under ``root``."""
    folder = root / "template-model"
    if not (folder / "manifest.json").is_file():
        from spcotmhp.datasets.loader import load_dataset
        from spcotmhp.datasets.synthetic import generate_environment, write_dataset
        from spcotmhp.learning.io import save_model
        from spcotmhp.learning.supervised import fit_supervised

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            data = write_dataset(generate_environment("flat", seed=1, n_rooms=4), root / "template-data")
            save_model(fit_supervised(load_dataset(data)), folder)
    return folder


def learner_model(root: Path) -> Path:
    """A 4-sweep SpCoTMHP fit of the template's dataset, with its learner state (learner.json, learner.npz)."""
    folder = root / "learner-model"
    if not (folder / "manifest.json").is_file():
        from spcotmhp.datasets.loader import load_dataset
        from spcotmhp.learning.gibbs import SpCoTMHP
        from spcotmhp.learning.io import save_model

        template_model(root)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            save_model(SpCoTMHP(iterations=4, seed=4).fit(load_dataset(root / "template-data")).model_, folder)
    return folder


def learner_edited(change: Callable[[dict], None]) -> Callable[[Path], list[str]]:
    """The learner model with its learner.npz arrays changed by ``change(arrays)`` (resealed), then `teach`."""

    def build(root: Path) -> list[str]:
        from tests.helpers.learning import reseal

        folder = root / f"m-learner-{change.__name__}"
        shutil.rmtree(folder, ignore_errors=True)
        shutil.copytree(learner_model(root), folder)
        with np.load(folder / "learner.npz") as npz:
            arrays = {k: npz[k] for k in npz.files}
        change(arrays)
        np.savez(folder / "learner.npz", **arrays)
        reseal(folder)
        x, y = template_start(root)
        return ["teach", str(folder), "this is the kitchen", "--at", f"{x:.3f}", f"{y:.3f}"]

    return build


def _counts_zeroed(a: dict) -> None:
    for name in ("n_k", "n_l", "n_lk", "W_lv", "trans"):
        a[name][...] = 0


def _scatter_negative(a: dict) -> None:
    a["sxx"][...] = -1e6


def _scatter_huge(a: dict) -> None:
    a["sx"][...] = 1e300
    a["sxx"][...] = 1e300


def _events_far(a: dict) -> None:
    a["X"][...] = 1e300


def door_model(root: Path) -> Path:
    """The four-room home of tests/helpers/planning.py with the bedroom #1 - corridor door closed: bedroom #1
    alone (the smaller region) | corridor, kitchen, bedroom #2."""
    folder = root / "door-model"
    if not (folder / "manifest.json").is_file():
        from spcotmhp.learning.io import save_model
        from tests.helpers.planning import DOORS, EDGES, NAMES, ROOMS, SHAPE, make_home

        save_model(make_home(ROOMS, DOORS[1:], NAMES, EDGES, SHAPE), folder)
    return folder


def door_plan(instruction: str, row: int, col: int) -> Callable[[Path], list[str]]:
    """`plan` on the closed-door home from the cell (row, col)."""

    def build(root: Path) -> list[str]:
        from spcotmhp.learning.io import load_model

        x, y = load_model(door_model(root)).require_map().cell_to_world(np.array([row, col]))
        return ["plan", str(door_model(root)), instruction, "--start", f"{x:.3f}", f"{y:.3f}"]

    return build


def copy_model(root: Path, name: str) -> Path:
    folder = root / name
    if folder.exists():
        shutil.rmtree(folder)
    shutil.copytree(template_model(root), folder)
    return folder


def plan_args(folder: Path) -> list[str]:
    """`plan FOLDER "go to the <first word>" --start <a free cell of the template>`."""
    meta = json.loads((template_model(folder.parent) / "model.json").read_text(encoding="utf-8"))
    word = "kitchen" if "kitchen" in meta["vocabulary"] else meta["vocabulary"][0]
    x, y = template_start(folder.parent)
    return ["plan", str(folder), f"go to the {word}", "--start", f"{x:.3f}", f"{y:.3f}"]


def template_start(root: Path) -> tuple[float, float]:
    cache = root / "template-start.json"
    if not cache.is_file():
        from spcotmhp.learning.io import load_model

        model = load_model(template_model(root))
        occ = model.require_map()
        rows, cols = np.nonzero(occ.data == 0)
        centre = np.array(occ.data.shape) / 2
        i = int(np.argmin((rows - centre[0]) ** 2 + (cols - centre[1]) ** 2))
        cache.write_text(json.dumps(occ.cell_to_world(np.array([rows[i], cols[i]])).tolist()), encoding="utf-8")
    x, y = json.loads(cache.read_text(encoding="utf-8"))
    return float(x), float(y)


def edited(*edits: tuple) -> Callable[[Path], list[str]]:
    """A model folder with ``edits`` (tests/helpers/strategies.py ``apply_edits``: resealed), then `plan`."""

    def build(root: Path) -> list[str]:
        from tests.helpers.strategies import apply_edits

        folder = copy_model(root, "m-" + re.sub(r"\W+", "-", str(edits))[:60])
        apply_edits(folder, list(edits))
        return plan_args(folder)

    return build


def rewritten(change: Callable[[Path], None]) -> Callable[[Path], list[str]]:
    """A model folder changed by ``change(folder)`` and resealed, then `plan`."""

    def build(root: Path) -> list[str]:
        from tests.helpers.learning import reseal

        folder = copy_model(root, "m-" + change.__name__)
        change(folder)
        reseal(folder)
        return plan_args(folder)

    return build


def _arrays(folder: Path) -> dict:
    with np.load(folder / "arrays.npz") as npz:
        return {k: npz[k] for k in npz.files}


def _meta(folder: Path, **changes) -> None:
    meta = json.loads((folder / "model.json").read_text(encoding="utf-8"))
    for key, value in changes.items():
        where = meta
        *path, last = key.split("__")
        for part in path:
            where = where[part]
        where[last] = value
    (folder / "model.json").write_text(json.dumps(meta), encoding="utf-8")


def grown(name: str, size: int, list_size: bool) -> Callable[[Path], list[str]]:
    """The file ``name`` of a model folder grown (sparse) to ``size`` bytes; with ``list_size`` the manifest lists
    the new size (its checksum stale), so the size check itself, not the manifest's, must refuse it."""

    def build(root: Path) -> list[str]:
        folder = copy_model(root, f"m-grown-{name}-{list_size}")
        with open(folder / name, "r+b") as handle:
            handle.truncate(size)
        if list_size:
            manifest = json.loads((folder / "manifest.json").read_text(encoding="utf-8"))
            manifest["files"][name]["bytes"] = size
            (folder / "manifest.json").write_text(json.dumps(manifest), encoding="utf-8")
        return plan_args(folder)

    return build


def learner_grown(root: Path) -> list[str]:
    """learner.json raised to its largest E and T (resealed), learner.npz grown to what they allow (sparse) and
    listed so: the bound the learner state allows, hashed."""
    from spcotmhp.learning.learner_state import MAX_EVENTS, MAX_TOKENS
    from spcotmhp.learning.model_checks import file_bound
    from tests.helpers.learning import reseal

    folder = copy_model(root, "m-learner-grown")
    if not (folder / "learner.json").is_file():
        (folder / "learner.json").write_text(
            json.dumps({"format": "spcotmhp-learner", "format_version": 1, "replay": True, "background": False}),
            encoding="utf-8",
        )
        (folder / "learner.npz").write_bytes(b"")
    learner = json.loads((folder / "learner.json").read_text(encoding="utf-8"))
    learner.update(E=MAX_EVENTS, T=MAX_TOKENS)
    (folder / "learner.json").write_text(json.dumps(learner), encoding="utf-8")
    meta = json.loads((folder / "model.json").read_text(encoding="utf-8"))
    size, _ = file_bound("learner.npz", meta, learner)
    (folder / "learner.npz").write_bytes(b"")
    reseal(folder)  # the small files with real checksums; learner.npz listed by its size (a stale checksum)
    with open(folder / "learner.npz", "r+b") as handle:
        handle.truncate(size)
    manifest = json.loads((folder / "manifest.json").read_text(encoding="utf-8"))
    manifest["files"]["learner.npz"]["bytes"] = size
    (folder / "manifest.json").write_text(json.dumps(manifest), encoding="utf-8")
    return plan_args(folder)


# ---- map images ---------------------------------------------------------------------------------------------
MAP_YAML = (
    "image: {image}\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
)


def costmap_of(image_name: str, image: Callable[[Path], None], yaml: str = MAP_YAML) -> Callable[[Path], list[str]]:
    """A map folder with the image ``image(path)`` writes, then `costmap map.yaml --out out.csv`."""

    def build(root: Path) -> list[str]:
        folder = root / f"map-{image.__name__}"
        shutil.rmtree(folder, ignore_errors=True)
        folder.mkdir(parents=True)
        image(folder / image_name)
        (folder / "map.yaml").write_text(yaml.format(image=image_name), encoding="utf-8")
        return ["costmap", str(folder / "map.yaml"), "--out", str(folder / "out.csv")]

    return build


def pgm_comment_50mb(path: Path) -> None:
    path.write_bytes(b"P5\n#" + b"x" * 50_000_000 + b"\n4 4\n255\n" + bytes([254]) * 16)


def pgm_strip(path: Path) -> None:
    path.write_bytes(b"P5\n1 16000000\n255\n" + bytes([254]) * 16_000_000)


def pgm_strip_wide(path: Path) -> None:
    path.write_bytes(b"P5 16000000 1 255 " + bytes([254]) * 16_000_000)


def pgm_spaces_50mb(path: Path) -> None:
    path.write_bytes(b"P5" + b" " * 50_000_000 + b"4 4 255\n" + bytes([254]) * 16)


def pgm_zeros_50mb(path: Path) -> None:
    path.write_bytes(b"P5\n" + b"0" * 50_000_000 + b"4 4\n255\n" + bytes([254]) * 16)


def pgm_comments_many(path: Path) -> None:
    path.write_bytes(b"P5\n" + b"#\n" * 5_000_000 + b"4 4\n255\n" + bytes([254]) * 16)


def pgm_huge_header_sparse(path: Path) -> None:
    """A PGM whose comment runs 8 GiB (a sparse file of zero bytes after '#')."""
    with open(path, "wb") as handle:
        handle.write(b"P5\n#")
        handle.truncate(SPARSE)


def pgm_cap_square(path: Path) -> None:
    path.write_bytes(b"P5\n4000 4000\n255\n" + bytes([254]) * 16_000_000)


def plain_pgm_cap(path: Path) -> None:
    """A plain (ASCII) PGM at the pixel cap: 64 MB of text that Pillow decodes in Python."""
    path.write_bytes(b"P2\n4000 4000\n255\n" + b"254\n" * 16_000_000)


def plain_ppm(path: Path) -> None:
    path.write_bytes(b"P3\n1000 1000\n255\n" + b"254 254 254\n" * 1_000_000)


def _png(width: int, height: int, rows: bytes, extra: bytes = b"") -> bytes:
    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    ihdr = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    return (
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", ihdr)
        + extra
        + chunk(b"IDAT", zlib.compress(rows, 9))
        + chunk(b"IEND", b"")
    )


def png_strip(path: Path) -> None:
    path.write_bytes(_png(16_000_000, 1, b"\0" + bytes([254]) * 16_000_000))


def png_text_50mb(path: Path) -> None:
    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    text = chunk(b"tEXt", b"Comment\0" + b"x" * 50_000_000)
    path.write_bytes(_png(4, 4, (b"\0" + bytes([254]) * 4) * 4, text))


def png_ztxt_bomb(path: Path) -> None:
    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    text = chunk(b"zTXt", b"Comment\0\0" + zlib.compress(b"x" * 500_000_000, 9))
    path.write_bytes(_png(4, 4, (b"\0" + bytes([254]) * 4) * 4, text))


def bmp_strip(path: Path) -> None:
    width, height = 16_000_000, 1
    row = (width + 3) // 4 * 4
    header = b"BM" + struct.pack("<IHHI", 54 + 1024 + row * height, 0, 0, 54 + 1024)
    info = struct.pack("<IiiHHIIiiII", 40, width, height, 1, 8, 0, row * height, 2835, 2835, 256, 0)
    palette = b"".join(bytes([i, i, i, 0]) for i in range(256))
    path.write_bytes(header + info + palette + bytes([254]) * row)


def yaml_alias_bomb(root: Path) -> list[str]:
    folder = root / "map-yaml-bomb"
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    (folder / "m.pgm").write_bytes(b"P5\n4 4\n255\n" + bytes([254]) * 16)
    lines = ['a0: &a0 ["x","x","x","x","x","x","x","x","x","x"]']
    lines += [f"a{i}: &a{i} [" + ",".join([f"*a{i - 1}"] * 10) + "]" for i in range(1, 9)]
    text = MAP_YAML.format(image="m.pgm") + "\n".join(lines) + "\n"
    (folder / "map.yaml").write_text(text, encoding="utf-8")
    return ["costmap", str(folder / "map.yaml"), "--out", str(folder / "out.csv")]


def yaml_tiny_resolution(root: Path) -> list[str]:
    folder = root / "map-tiny-res"
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    (folder / "m.pgm").write_bytes(b"P5\n40 40\n255\n" + bytes([254]) * 1600)
    (folder / "map.yaml").write_text(MAP_YAML.format(image="m.pgm").replace("0.05", "1e-300"), encoding="utf-8")
    return ["costmap", str(folder / "map.yaml"), "--out", str(folder / "out.csv")]


# ---- the service, saving, the library ------------------------------------------------------------------------
def busy_port_missing_model(root: Path) -> list[str]:
    """`serve` a missing model on a port held by this process (the socket stays open while the case runs)."""
    sock = socket.socket()
    sock.bind(("127.0.0.1", 0))
    sock.listen(1)
    _HELD.append(sock)
    return ["serve", str(root / "no-such-model"), "--port", str(sock.getsockname()[1])]


def busy_port_bad_model(root: Path) -> list[str]:
    from tests.helpers.strategies import apply_edits

    folder = copy_model(root, "m-serve-bad")
    apply_edits(folder, [("array", "Sigma", "scale", 1e-300)])
    sock = socket.socket()
    sock.bind(("127.0.0.1", 0))
    sock.listen(1)
    _HELD.append(sock)
    return ["serve", str(folder), "--port", str(sock.getsockname()[1])]


_HELD: list[socket.socket] = []


def lib(name: str) -> Callable[[Path], list[str]]:
    def build(root: Path) -> list[str]:
        template_model(root)
        if name.startswith("door"):
            door_model(root)
        return [f"lib:{name}", str(root)]

    build.__name__ = name
    return build


def library_case(name: str, root: Path) -> str:
    """Run the library case ``name`` (module docstring) and return what it found (a SpcotmhpError escapes)."""
    from spcotmhp.learning.io import load_model, save_model
    from spcotmhp.planning import HierarchicalPlanner

    model_dir = template_model(root)
    if name.startswith("start-"):
        starts = {
            "start-strings": ["1", "2"],
            "start-numpy-strings": np.array(["1", "2"]),
            "start-bytes": b"12",
            "start-string": "1 2",
            "start-bools": (True, False),
            "start-three": [1.0, 2.0, 3.0],
            "start-nested": [[1.0, 2.0]],
            "start-dict": {"x": 1.0, "y": 2.0},
            "start-complex": [complex(1, 0), 2.0],
            "start-nan": [float("nan"), 0.0],
            "start-huge": [1e308, 1e308],
            "start-object-array": np.array([1.0, "2"], dtype=object),
        }
        model = load_model(model_dir)
        word = "kitchen" if "kitchen" in model.vocabulary else model.vocabulary[0]
        plan = HierarchicalPlanner(model).plan(f"go to the {word}", starts[name])
        return f"planned {plan.length_m:.2f} m from {starts[name]!r}"
    if name == "save-default-no-overwrite":
        folder = root / "lib-saved"
        shutil.rmtree(folder, ignore_errors=True)
        model = load_model(model_dir)
        save_model(model, folder)
        save_model(model, folder)
        return "the second save_model without overwrite replaced the model"
    if name.startswith("umask-"):
        mask = int(name.removeprefix("umask-"), 8)
        folder = root / f"lib-umask-{name}"
        shutil.rmtree(folder, ignore_errors=True)
        old = os.umask(mask)
        try:
            save_model(load_model(model_dir), folder)
        finally:
            os.umask(old)
        modes = {p.name: oct(p.stat().st_mode & 0o777) for p in [folder, *sorted(folder.iterdir())]}
        want_dir, want_file = oct(0o777 & ~mask), oct(0o666 & ~mask)
        wrong = {n: m for n, m in modes.items() if m != (want_dir if n == folder.name else want_file)}
        if wrong:
            raise AssertionError(f"modes under umask {mask:03o}: {wrong} (want {want_dir} / {want_file})")
        return f"modes under umask {mask:03o}: folder {want_dir}, files {want_file}"
    if name == "staging-after-kill":
        return staging_after_kill(root, model_dir)
    if name in ("door-same-region", "door-cut-off"):
        from tests.helpers.planning import world

        model = load_model(door_model(root))
        occ = model.require_map()
        goal = "bedroom" if name == "door-same-region" else "kitchen"
        plan = HierarchicalPlanner(model).plan(f"go to the {goal}", world(occ, 6, 5))
        return f"planned to {plan.places[-1].label} ({plan.length_m:.2f} m)"
    raise KeyError(name)


def staging_after_kill(root: Path, model_dir: Path) -> str:
    """SIGKILL a process in the middle of saving a model (its arrays written, its manifest not): a staging folder
    is left; the next save in another process removes it."""
    target = root / "killed-save"
    shutil.rmtree(target, ignore_errors=True)
    for old in root.glob(".killed-save.*"):
        shutil.rmtree(old, ignore_errors=True)
    script = (
        "import sys, time, numpy as np\n"
        "import spcotmhp.learning.model_folder as mf\n"
        "from spcotmhp.learning.io import load_model, save_model\n"
        "real = mf.manifest_of\n"
        "def slow(*a):\n"
        "    print('writing', flush=True); time.sleep(60); return real(*a)\n"
        "mf.manifest_of = slow\n"
        f"save_model(load_model({str(model_dir)!r}), {str(target)!r})\n"
    )
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True, env=_env())
    assert proc.stdout is not None and proc.stdout.readline().strip() == "writing"
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait(10)
    left = sorted(p.name for p in root.glob(".killed-save.*"))
    if not left:
        raise AssertionError("the killed save left no staging folder (the case did not interrupt it)")
    again = f"from spcotmhp.learning.io import *; save_model(load_model({str(model_dir)!r}), {str(target)!r})"
    subprocess.run([sys.executable, "-c", again], check=True, env=_env(), capture_output=True)
    after = sorted(p.name for p in root.glob(".killed-save.*"))
    if after:
        raise AssertionError(f"staging folders left after the next save: {after}")
    return f"the killed save left {left}; the next save removed them"


# ---- the cases ----------------------------------------------------------------------------------------------
def _mu_far(folder: Path) -> None:
    a = _arrays(folder)
    a["mu"][:] = 9.9e5
    np.savez(folder / "arrays.npz", **a)


def _sigma_not_pd(folder: Path) -> None:
    a = _arrays(folder)
    a["Sigma"][0] = [[1.0, 2.0], [2.0, 1.0]]
    np.savez(folder / "arrays.npz", **a)


def _phi_negative(folder: Path) -> None:
    a = _arrays(folder)
    a["phi"][0, 1] += a["phi"][0, 0] + 0.25
    a["phi"][0, 0] = -0.25
    np.savez(folder / "arrays.npz", **a)


def _no_active_places(folder: Path) -> None:
    a = _arrays(folder)
    a["active_places"][:] = False
    np.savez(folder / "arrays.npz", **a)


def _float16_mu(folder: Path) -> None:
    a = _arrays(folder)
    a["mu"] = a["mu"].astype(np.float16) * np.float16(60000)
    np.savez(folder / "arrays.npz", **a)


def _extra_member(folder: Path) -> None:
    a = _arrays(folder)
    a["../../evil"] = np.zeros(3)
    np.savez(folder / "arrays.npz", **a)


def _theta_without_D(folder: Path) -> None:
    a = _arrays(folder)
    a["theta"] = np.full((len(a["pi"]), 3), 1 / 3)
    np.savez(folder / "arrays.npz", **a)


def _empty_word(folder: Path) -> None:
    meta = json.loads((folder / "model.json").read_text(encoding="utf-8"))
    meta["vocabulary"][-1] = ""
    (folder / "model.json").write_text(json.dumps(meta), encoding="utf-8")


def _space_word(folder: Path) -> None:
    meta = json.loads((folder / "model.json").read_text(encoding="utf-8"))
    meta["vocabulary"][-1] = " \n\t"
    (folder / "model.json").write_text(json.dumps(meta), encoding="utf-8")


def _huge_int_K(folder: Path) -> None:
    text = (folder / "model.json").read_text(encoding="utf-8")
    (folder / "model.json").write_text(re.sub(r'"K": \d+', '"K": ' + "9" * 5000, text, count=1), encoding="utf-8")


def _deep_info(folder: Path) -> None:
    text = (folder / "model.json").read_text(encoding="utf-8")
    deep = '"info": {"x": ' + "[" * 100_000 + "]" * 100_000 + ", "
    (folder / "model.json").write_text(text.replace('"info": {', deep, 1), encoding="utf-8")


def _map_resolution(folder: Path) -> None:
    text = (folder / "map.yaml").read_text(encoding="utf-8")
    (folder / "map.yaml").write_text(re.sub(r"resolution: .*", "resolution: 1e-300", text), encoding="utf-8")


def _map_origin(folder: Path) -> None:
    text = (folder / "map.yaml").read_text(encoding="utf-8")
    (folder / "map.yaml").write_text(re.sub(r"origin: .*", "origin: [1e308, -1e308, 0.0]", text), encoding="utf-8")


def _map_is(target: str) -> Callable[[Path], None]:
    def change(folder: Path) -> None:
        _meta(folder, map=target)

    change.__name__ = "_map_is_" + re.sub(r"\W+", "_", target)
    return change


def _image_fifo(folder: Path) -> None:
    """map.yaml's image a named pipe (unlisted in the manifest): opening it for reading would block."""
    os.mkfifo(folder / "pipe.pgm")
    text = (folder / "map.yaml").read_text(encoding="utf-8")
    (folder / "map.yaml").write_text(re.sub(r"image: .*", "image: pipe.pgm", text), encoding="utf-8")


def fifo_image(path: Path) -> None:
    os.mkfifo(path)


def dev_zero_image(path: Path) -> None:
    path.symlink_to("/dev/zero")


def _psi_identity(folder: Path) -> None:
    a = _arrays(folder)
    a["psi"] = np.eye(len(a["psi"]))
    np.savez(folder / "arrays.npz", **a)


def _W_one_word(folder: Path) -> None:
    a = _arrays(folder)
    a["W"][:] = 0.0
    a["W"][:, 0] = 1.0
    np.savez(folder / "arrays.npz", **a)


def _env() -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(REPO) + os.pathsep + env.get("PYTHONPATH", "")
    return env


CASES: list[Case] = [
    # -- values a checksum cannot judge (issue item 1) --
    Case("place_size 1e308", "values", edited(("hyper", "place_size", 1e308)), expect="place_size"),
    Case("Sigma x 1e-300", "values", edited(("array", "Sigma", "scale", 1e-300)), expect="Sigma"),
    Case("Sigma x 1e150", "values", edited(("array", "Sigma", "scale", 1e150)), expect="Sigma"),
    Case("mu NaN", "values", edited(("array", "mu", "entry", float("nan"))), expect="mu"),
    Case("W +inf", "values", edited(("array", "W", "entry", float("inf"))), expect="W"),
    Case("Sigma not PD", "values", rewritten(_sigma_not_pd), expect="Sigma"),
    Case("pi x 2 (sums to 2)", "values", edited(("array", "pi", "scale", 2.0)), expect="pi"),
    Case("psi column zeroed", "values", edited(("array", "psi", "zero-column", 0.0)), expect="psi"),
    Case("phi negative, rows sum to 1", "values", rewritten(_phi_negative), expect="phi"),
    Case("alpha -1", "values", edited(("hyper", "alpha", -1.0)), expect="alpha"),
    Case("nu0 0.5", "values", edited(("hyper", "nu0", 0.5)), expect="nu0"),
    Case("kappa0 1e300", "values", edited(("hyper", "kappa0", 1e300)), expect="kappa0"),
    Case("hyper K 0", "values", edited(("hyper", "K", 0)), expect=r"\bK\b"),
    Case("V0 1e-300 I", "values", edited(("hyper", "V0", [[1e-300, 0.0], [0.0, 1e-300]])), expect="V0"),
    Case("off_name -1", "values", edited(("hyper", "off_name", -1.0)), expect="off_name"),
    Case("costmap inflation 1e308", "values", edited(("costmap", "inflation_radius", 1e308)), expect="inflation"),
    # -- variants: other keys, other arrays --
    Case("v: costmap inflation 1e4 m (in range)", "variant", edited(("costmap", "inflation_radius", 1e4)), 0),
    Case("v: costmap inscribed 1e4 m (in range)", "variant", edited(("costmap", "inscribed_radius", 1e4)), 2, ""),
    Case("v: place_size 1e5 (the bound)", "variant", edited(("hyper", "place_size", 1e5)), 0),
    Case("v: m0 strings", "variant", edited(("hyper", "m0", ["a", "b"])), expect="m0"),
    Case("v: hyper L 10**20", "variant", edited(("hyper", "L", 10**20)), expect=r"\bL\b"),
    Case("v: feature_weight NaN", "variant", edited(("info", "feature_weight", float("nan"))), expect="feature_weight"),
    Case("v: means 990 km away", "variant", rewritten(_mu_far), 2, ""),
    Case("v: no active place", "variant", rewritten(_no_active_places), 2, ""),
    Case("v: mu float16 overflow", "variant", rewritten(_float16_mu), expect="mu"),
    Case("v: npz member ../../evil", "variant", rewritten(_extra_member), expect="unknown member"),
    Case("v: theta without D", "variant", rewritten(_theta_without_D), expect="theta"),
    Case("v: empty vocabulary word", "variant", rewritten(_empty_word), expect="vocabulary"),
    Case("v: whitespace vocabulary word", "variant", rewritten(_space_word), expect="vocabulary"),
    Case("v: K of 5000 digits", "variant", rewritten(_huge_int_K), expect="model.json"),
    Case("v: info nested 100000 deep", "variant", rewritten(_deep_info), expect="model.json"),
    Case("v: map resolution 1e-300", "variant", rewritten(_map_resolution), expect="resolution"),
    Case("v: map origin 1e308", "variant", rewritten(_map_origin), expect="origin"),
    Case("v: psi the identity", "variant", rewritten(_psi_identity), 0),
    Case("v: W all mass on one word", "variant", rewritten(_W_one_word), expect="kitchen"),
    Case("v: model.json map -> arrays.npz", "variant", rewritten(_map_is("arrays.npz")), expect="map"),
    Case("v: model.json map -> .", "variant", rewritten(_map_is(".")), expect="map"),
    Case("v: model.json map -> /etc/passwd", "variant", rewritten(_map_is("/etc/passwd")), expect="map"),
    Case("v: map image a FIFO (unlisted)", "variant", rewritten(_image_fifo), expect="pipe.pgm"),
    Case("v: teach: learner counts zeroed", "variant", learner_edited(_counts_zeroed), expect="learner"),
    Case("v: teach: learner scatter -1e6", "variant", learner_edited(_scatter_negative), expect="learner"),
    Case("v: teach: learner scatter 1e300", "variant", learner_edited(_scatter_huge), expect="learner"),
    Case("v: teach: learner events at 1e300 m", "variant", learner_edited(_events_far), expect="learner"),
    # -- sizes (issue item 2) --
    Case("arrays.npz 8 GiB sparse", "sizes", grown("arrays.npz", SPARSE, False), expect="arrays.npz"),
    Case("v: arrays.npz 8 GiB, manifest lists it", "variant", grown("arrays.npz", SPARSE, True), expect="arrays.npz"),
    Case("v: map.pgm 8 GiB, manifest lists it", "variant", grown("map.pgm", SPARSE, True), expect="map.pgm"),
    Case("v: model.json 8 GiB, manifest lists it", "variant", grown("model.json", SPARSE, True), expect="model.json"),
    Case("v: manifest.json 8 GiB", "variant", grown("manifest.json", SPARSE, False), expect="manifest"),
    Case("v: learner.npz at learner.json's E, T caps", "variant", learner_grown, expect="learner"),
    Case("PGM 50 MB comment", "sizes", costmap_of("m.pgm", pgm_comment_50mb), expect="m.pgm"),
    Case("PGM 1 x 16,000,000", "sizes", costmap_of("m.pgm", pgm_strip), expect="m.pgm"),
    Case("v: PGM 16,000,000 x 1, one-line header", "variant", costmap_of("m.pgm", pgm_strip_wide), expect="m.pgm"),
    Case("v: PGM 50 MB of spaces", "variant", costmap_of("m.pgm", pgm_spaces_50mb), expect="m.pgm"),
    Case("v: PGM 50 MB of leading zeros", "variant", costmap_of("m.pgm", pgm_zeros_50mb), expect="m.pgm"),
    Case("v: PGM 5,000,000 empty comments", "variant", costmap_of("m.pgm", pgm_comments_many), expect="m.pgm"),
    Case("v: PGM 8 GiB comment (sparse)", "variant", costmap_of("m.pgm", pgm_huge_header_sparse), expect="m.pgm"),
    Case("v: plain PGM (P2) 4000 x 4000", "variant", costmap_of("m.pgm", plain_pgm_cap), expect="plain"),
    Case("v: plain PPM (P3) 1000 x 1000", "variant", costmap_of("m.ppm", plain_ppm), expect="plain"),
    Case("v: map image a FIFO", "variant", costmap_of("m.pgm", fifo_image), expect="m.pgm"),
    Case("v: map image -> /dev/zero", "variant", costmap_of("m.pgm", dev_zero_image), expect="m.pgm"),
    Case("v: PNG 16,000,000 x 1", "variant", costmap_of("m.png", png_strip), expect="m.png"),
    Case("v: PNG 50 MB tEXt", "variant", costmap_of("m.png", png_text_50mb), 0),
    Case("v: PNG zTXt of 500 MB", "variant", costmap_of("m.png", png_ztxt_bomb), expect="m.png"),
    Case("v: BMP 16,000,000 x 1", "variant", costmap_of("m.bmp", bmp_strip), expect="m.bmp"),
    Case("v: map YAML alias bomb", "variant", yaml_alias_bomb, expect="map.yaml"),
    Case("v: map resolution 1e-300", "variant", yaml_tiny_resolution, expect="resolution"),
    Case("v: PGM 4000 x 4000 (the pixel cap)", "variant", costmap_of("m.pgm", pgm_cap_square), 0, slow=True),
    # -- a map cut by a closed door (issue item 4) --
    Case("door: goal in the start's small region", "regions", door_plan("go to the bedroom", 6, 5), 0),
    Case(
        "door: goal only behind the door",
        "regions",
        door_plan("go to the kitchen", 6, 5),
        expect="the kitchen is not reachable from here.*the free space is cut",
    ),
    Case(
        "v: door: waypoint behind the door",
        "variant",
        door_plan("go to the bedroom via the corridor", 6, 5),
        expect="the corridor is not reachable",
    ),
    Case("v: door: start in the wall", "variant", door_plan("go to the bedroom", 5, 10), expect="start"),
    # -- small things (issue item 5) --
    Case("serve: busy port, missing model", "small", busy_port_missing_model, expect="no-such-model"),
    Case("v: serve: busy port, Sigma x 1e-300", "variant", busy_port_bad_model, expect="Sigma"),
    Case("umask 022", "small", lib("umask-022"), 0),
    Case("v: umask 077", "variant", lib("umask-077"), 0),
    Case("v: umask 002", "variant", lib("umask-002"), 0),
    Case("SIGKILLed save, next save cleans", "small", lib("staging-after-kill"), 0),
    Case("save_model overwrite=False", "small", lib("save-default-no-overwrite"), expect="already holds a model"),
    Case('start ["1", "2"]', "small", lib("start-strings"), expect="start"),
    Case('v: start np.array(["1", "2"])', "variant", lib("start-numpy-strings"), expect="start"),
    Case("v: start b'12'", "variant", lib("start-bytes"), expect="start"),
    Case('v: start "1 2"', "variant", lib("start-string"), expect="start"),
    Case("v: start (True, False)", "variant", lib("start-bools"), expect="start"),
    Case("v: start of 3 numbers", "variant", lib("start-three"), expect="start"),
    Case("v: start [[1, 2]]", "variant", lib("start-nested"), expect="start"),
    Case("v: start a dict", "variant", lib("start-dict"), expect="start"),
    Case("v: start complex", "variant", lib("start-complex"), expect="start"),
    Case("v: start NaN", "variant", lib("start-nan"), expect="start"),
    Case("v: start 1e308", "variant", lib("start-huge"), expect="start"),
    Case("v: start object array", "variant", lib("start-object-array"), expect="start"),
]


# ---- running and judging ------------------------------------------------------------------------------------
def run(case: Case, root: Path, timeout: float = 120.0) -> tuple[list[str], Outcome]:
    """Build ``case`` under ``root`` and run it in a fresh process; (command, outcome)."""
    args = case.build(root)
    if args[0].startswith("lib:"):
        argv = [sys.executable, "-m", "tests.helpers.hostile_cases", "--lib", args[0][4:], *args[1:]]
    else:
        argv = [EXE, *args]
    t0 = time.perf_counter()
    try:
        proc = subprocess.run(
            argv, capture_output=True, text=True, timeout=timeout, env={**_env(), **case.env}, cwd=root
        )
        outcome = Outcome(proc.returncode, time.perf_counter() - t0, proc.stdout, proc.stderr)
    except subprocess.TimeoutExpired as exc:
        outcome = Outcome(-9, time.perf_counter() - t0, str(exc.stdout or ""), f"timed out after {timeout} s")
    finally:
        for sock in _HELD:
            sock.close()
        _HELD.clear()
    return args, outcome


def judge(case: Case, outcome: Outcome) -> str:
    """'' when ``outcome`` is what ``case`` asks (module docstring), else what is wrong."""
    text = outcome.stdout + outcome.stderr
    if "Traceback" in text:
        return "traceback: " + outcome.stderr.strip().splitlines()[-1][:200]
    if outcome.status != case.status:
        return f"exit {outcome.status}, expected {case.status}: {(outcome.stderr or outcome.stdout).strip()[-200:]}"
    if case.status == 2:
        lines = outcome.error_lines
        if len(lines) != 1 or not lines[0].startswith("error: "):
            return f"not one error: line on stderr: {lines[:3]}"
        if case.expect and not re.search(case.expect, lines[0]):
            return f"the error does not say {case.expect!r}: {lines[0][:200]}"
    return ""


def _shown(args: list[str], root: Path) -> str:
    return " ".join(a if len(a) < 60 else a[:57] + "..." for a in args).replace(str(root) + "/", "")


def main(argv: list[str]) -> int:
    import tempfile

    if argv[:1] == ["--lib"]:
        from spcotmhp.errors import SpcotmhpError

        try:
            print("ok: " + library_case(argv[1], Path(argv[2])))
        except SpcotmhpError as exc:
            print(f"error: {exc}", file=sys.stderr)
            return 2
        return 0
    root = Path(argv[0]) if argv and not argv[0].startswith("-") else Path(tempfile.mkdtemp(prefix="hostile-"))
    names = argv[1:] if argv and not argv[0].startswith("-") else []
    root.mkdir(parents=True, exist_ok=True)
    template_model(root)
    door_model(root)
    print(f"{'case':44s} {'exit':>4s} {'wall s':>7s}  {'judged':8s} command / first line")
    bad = 0
    for case in CASES:
        if names and not any(n in case.name for n in names):
            continue
        args, outcome = run(case, root)
        verdict = judge(case, outcome)
        bad += bool(verdict)
        first = (outcome.error_lines or outcome.stdout.strip().splitlines() or [""])[0]
        print(
            f"{case.name[:44]:44s} {outcome.status:4d} {outcome.seconds:7.2f}  {'ok' if not verdict else 'FAIL':8s} "
            f"{_shown(args, root)}"
        )
        print(f"{'':44s} {'':4s} {'':7s}  {'':8s} -> {(verdict or first)[:160]}")
    print(f"{bad} case(s) failed")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
