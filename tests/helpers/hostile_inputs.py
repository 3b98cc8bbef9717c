"""Hostile map files, busy ports and library scripts for tests/helpers/hostile_cases.py: map images with hostile
headers (PGM comments and strips, plain PNM, PNG chunks, BMP, FIFOs), map YAML tricks, a port held while `serve`
starts, and the library cases run in a fresh interpreter (:func:`library_case`: starts, umask, saving)."""

from __future__ import annotations

import os
import shutil
import signal
import socket
import struct
import subprocess
import sys
import time
import zlib
from collections.abc import Callable
from pathlib import Path

import numpy as np

from tests.helpers.hostile_models import SPARSE, child_env, copy_model, door_model, template_model

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
    from spcotmhp.persistence.io import load_model, save_model
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
        "import spcotmhp.persistence.folder as mf\n"
        "from spcotmhp.persistence.io import load_model, save_model\n"
        "real = mf.manifest_of\n"
        "def slow(*a):\n"
        "    print('writing', flush=True); time.sleep(60); return real(*a)\n"
        "mf.manifest_of = slow\n"
        f"save_model(load_model({str(model_dir)!r}), {str(target)!r})\n"
    )
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True, env=child_env())
    assert proc.stdout is not None and proc.stdout.readline().strip() == "writing"
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait(10)
    # the next process starts 0.1 s later (a supervisor's restart delay at the least): a process's start is
    # known to a clock tick (10 ms) and taken 10 ms early, on the safe side, so a save killed within 20 ms of
    # the next process's start may be left for a later one
    time.sleep(0.1)
    left = sorted(p.name for p in root.glob(".killed-save.*"))
    if not left:
        raise AssertionError("the killed save left no staging folder (the case did not interrupt it)")
    again = f"from spcotmhp.persistence.io import *; save_model(load_model({str(model_dir)!r}), {str(target)!r})"
    subprocess.run([sys.executable, "-c", again], check=True, env=child_env(), capture_output=True)
    after = sorted(p.name for p in root.glob(".killed-save.*"))
    if after:
        raise AssertionError(f"staging folders left after the next save: {after}")
    return f"the killed save left {left}; the next save removed them"


def fifo_image(path: Path) -> None:
    os.mkfifo(path)


def dev_zero_image(path: Path) -> None:
    path.symlink_to("/dev/zero")
