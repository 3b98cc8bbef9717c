"""Generated hostile inputs for the hardening fuzz tests (importable, no pytest fixtures).

Each ``*_case(rng, folder, ...)`` writes one damaged map, dataset or model folder drawn from ``rng`` (a
``random.Random``) and returns a short label of what it did. ``run_case(call, label)`` runs a loader on it and
classifies the outcome: ``ok``, ``error`` (a library error with a one-line message) or ``traceback`` (anything
else), with its time. ``tests/test_safe_read_fuzz.py`` draws the seeds with hypothesis;
``python -m tests.helpers.hardening_corpus N`` runs N cases of each kind and prints the counts, slowest case
and peak memory.
"""

from __future__ import annotations

import json
import random
import shutil
import struct
import sys
import tempfile
import time
import tracemalloc
import zipfile
import zlib
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from spcotmhp.errors import SpcotmhpError

HOSTILE_NUMBERS = [
    "1" + "0" * 400,
    "1e400",
    "-1e400",
    "1e20",
    "1e308",
    "-1e308",
    ".nan",
    "nan",
    "inf",
    "-inf",
    "0",
    "-1",
    "1e-320",
    "9" * 25,
    "0x1F",
    "1_000",
    "true",
    "null",
    "[]",
    "{}",
    "''",
    "'abc'",
    "1e308",
    "4.9e-324",
]
MAP_BASE = {
    "image": "map.pgm",
    "resolution": "0.05",
    "origin": "[-1.0, -1.0, 0.0]",
    "negate": "0",
    "occupied_thresh": "0.65",
    "free_thresh": "0.196",
    "mode": "trinary",
}


def _pgm(rng: random.Random) -> bytes:
    kind = rng.randrange(10)
    if kind == 0:
        return f"P5\n{rng.choice([100000, 40000, 70000])} {rng.choice([100000, 40000])}\n255\n".encode()
    if kind == 1:
        return b"P5\n4 4\n255\n" + bytes(rng.randrange(16))  # truncated pixels
    if kind == 2:
        return bytes(rng.randrange(256) for _ in range(rng.randrange(1, 64)))  # noise
    if kind == 3:
        return b"%!PS-Adobe-3.0 EPSF-3.0\n%%BoundingBox: 0 0 10 10\nshowpage\n"  # must never reach Ghostscript
    if kind == 4:
        return b"P5\n0 0\n255\n"
    if kind == 5:
        return f"P5\n3 3\n{rng.choice([1, 255, 65535, 70000, 0])}\n".encode() + bytes(18)
    if kind == 6:  # issue 26: a header comment past the 64 KiB bound (50 MB took costmap 22 s)
        return b"P5\n#" + b"c" * rng.choice([70_000, 5_000_000]) + b"\n4 4\n255\n" + bytes(16)
    if kind == 7:  # issue 26: a strip inside the pixel cap (1 x 16,000,000 took costmap 22.7 s)
        n = rng.choice([1001, 100_000, 16_000_000])
        return f"P5\n1 {n}\n255\n".encode() + bytes([254]) * min(n, 200_000)
    w, h = rng.randrange(1, 40), rng.randrange(1, 40)
    return f"P5\n{w} {h}\n255\n".encode() + bytes(rng.choice([0, 205, 254]) for _ in range(w * h))


def _png(rng: random.Random) -> bytes:
    import io

    from PIL import Image

    buf = io.BytesIO()
    Image.fromarray(np.full((rng.randrange(1, 30), rng.randrange(1, 30)), 254, np.uint8)).save(buf, "PNG")
    data = bytearray(buf.getvalue())
    if rng.random() < 0.7:
        data[rng.randrange(8, len(data))] ^= 1 << rng.randrange(8)  # corrupt a chunk
    if rng.random() < 0.3:
        w, h = rng.choice([(8000, 8000), (100000, 100000), (1, 10**9)])
        data[16:24] = struct.pack(">II", w, h)  # a lying header (bad CRC too)
        data[29:33] = struct.pack(">I", zlib.crc32(bytes(data[12:29])))
    return bytes(data)


def map_case(rng: random.Random, folder: Path) -> str:
    """A map folder: map.yaml with hostile values, aliases, nesting or long names, and a hostile image."""
    keys = dict(MAP_BASE)
    label = []
    for _ in range(rng.randrange(0, 3)):
        key = rng.choice(list(keys))
        keys[key] = (
            rng.choice(HOSTILE_NUMBERS)
            if key != "image"
            else rng.choice(
                [
                    "a" * 5000 + ".pgm",
                    '"a\\0b.pgm"',
                    "map.eps",
                    "../../etc/passwd",
                    "/dev/zero",
                    "map.png",
                    "''",
                    "map.bmp",
                    "[1, 2]",
                    '"\\x01.pgm"',
                ]
            )
        )
        label.append(f"{key}={keys[key][:20]}")
    text = "".join(f"{k}: {v}\n" for k, v in keys.items() if rng.random() > 0.05)
    extra = rng.randrange(10)
    if extra == 0:
        text = (
            'a: &a ["lol","lol","lol","lol","lol","lol","lol","lol","lol"]\n'
            + "".join(f"{chr(98 + i)}: &{chr(98 + i)} [" + ",".join([f"*{chr(97 + i)}"] * 9) + "]\n" for i in range(8))
            + text
        )
        label.append("billion laughs")
    elif extra == 1:
        text += "deep: " + "[" * 5000 + "]" * 5000 + "\n"
        label.append("deep")
    elif extra == 2:
        text = text[: rng.randrange(len(text) + 1)]
        label.append("cut yaml")
    elif extra == 3:
        text += "x: " + "{a: " * 3000 + "1" + "}" * 3000 + "\n"
        label.append("deep mapping")
    (folder / "map.yaml").write_text(text, encoding="utf-8")
    (folder / "map.pgm").write_bytes(_pgm(rng))
    (folder / "map.png").write_bytes(_png(rng))
    (folder / "map.bmp").write_bytes(b"BM" + bytes(rng.randrange(256) for _ in range(rng.randrange(60))))
    (folder / "map.eps").write_bytes(_pgm(random.Random(3)))
    return ", ".join(label) or "plain"


def dataset_case(rng: random.Random, folder: Path, template: Path) -> str:
    """A copy of the dataset ``template`` with hostile cells, rows, bytes or extra files."""
    shutil.copytree(template, folder, dirs_exist_ok=True)
    names = sorted(p.name for p in folder.iterdir() if p.suffix == ".csv")
    target = folder / rng.choice(names)
    lines = target.read_text(encoding="utf-8").splitlines()
    kind = rng.randrange(6)
    if kind <= 2 and len(lines) > 1:
        i = rng.randrange(1, len(lines))
        cells = lines[i].split(",")
        j = rng.randrange(len(cells))
        cells[j] = rng.choice(HOSTILE_NUMBERS + ["", "x" * 200_000, "1e20", "-1e308", "1e308", '"', "\0"])
        lines[i] = ",".join(cells)
        label = f"{target.name} cell ({i},{j}) = {cells[j][:20]!r}"
    elif kind == 3:
        lines = lines[: rng.randrange(len(lines) + 1)]
        label = f"{target.name} cut to {len(lines)} lines"
    elif kind == 4:
        lines.insert(rng.randrange(len(lines) + 1), ",".join(rng.choice(HOSTILE_NUMBERS) for _ in range(6)))
        label = f"{target.name} extra row"
    else:
        data = bytearray("\n".join(lines).encode())
        if data:
            data[rng.randrange(len(data))] = rng.randrange(256)
        target.write_bytes(bytes(data))
        return f"{target.name} byte flipped"
    target.write_text("\n".join(lines) + "\n", encoding="utf-8")
    if rng.random() < 0.2:
        map_case(rng, folder)
        label += "; hostile map"
    return label


def model_case(rng: random.Random, folder: Path, template: Path) -> str:
    """A copy of the model folder ``template``, damaged: flipped bytes (sealed again or not), hostile JSON
    values, nesting, symlinks out, zip bombs, a bare .npy, a non-symmetric Sigma; hostile values resealed and
    files grown sparse to gigabytes (issue 26)."""
    from spcotmhp.persistence.folder import MANIFEST, manifest_of

    shutil.copytree(template, folder, dirs_exist_ok=True, symlinks=True)
    reseal = rng.random() < 0.7
    kind = rng.randrange(11)
    if kind == 9:  # issue 26: hostile values behind a valid checksum
        from tests.helpers.strategies import ISSUE_26_VALUES, apply_edits

        edit = rng.choice(ISSUE_26_VALUES)
        return apply_edits(folder, [edit]) + " (resealed)"
    if kind == 10:  # issue 26: a file grown sparse to gigabytes, its size (not its hash) in the manifest
        name, size = rng.choice(["arrays.npz", "map.pgm", "model.json", "map.yaml"]), rng.choice([2**30, 2**33])
        with open(folder / name, "r+b") as handle:
            handle.truncate(size)
        manifest = json.loads((folder / MANIFEST).read_text(encoding="utf-8"))
        manifest["files"][name]["bytes"] = size if rng.random() < 0.7 else manifest["files"][name]["bytes"]
        (folder / MANIFEST).write_text(json.dumps(manifest), encoding="utf-8")
        return f"{name} grown sparse to {size} bytes"
    if kind == 0:
        name = rng.choice(["arrays.npz", "model.json", "map.yaml", "map.pgm", MANIFEST])
        data = bytearray((folder / name).read_bytes())
        data[rng.randrange(len(data))] ^= 1 << rng.randrange(8)
        (folder / name).write_bytes(bytes(data))
        label = f"flipped byte in {name}"
    elif kind == 1:
        meta = json.loads((folder / "model.json").read_text(encoding="utf-8"))
        key = rng.choice(["K", "L", "V", "D", "vocabulary", "hyper", "costmap", "info", "map", "format_version"])
        value = rng.choice(
            [
                10**400,
                10**20,
                -1,
                0,
                1e308,
                "x" * 5000,
                None,
                [],
                {},
                True,
                2**63,
                {"inflation_radius": 1e308},
                "../outside.yaml",
                "/etc/passwd",
                "map.yaml\0",
            ]
        )
        meta[key] = value
        text = json.dumps(meta).replace("1e+308", "1e400" if rng.random() < 0.5 else "1e308")
        (folder / "model.json").write_text(text, encoding="utf-8")
        label = f"model.json {key} = {str(value)[:20]}"
    elif kind == 2:
        (folder / "model.json").write_text(
            '{"format": "spcotmhp-model", "info": ' + "[" * 5000 + "]" * 5000 + "}", encoding="utf-8"
        )
        label = "deep model.json"
    elif kind == 3:
        outside = folder.parent / f"outside-{rng.randrange(10**6)}"
        outside.mkdir()
        name = rng.choice(["arrays.npz", "model.json", "map.yaml", "map.pgm"])
        shutil.copy(folder / name, outside / name)
        (folder / name).unlink()
        (folder / name).symlink_to(outside / name)
        label = f"{name} symlinked out"
    elif kind == 4:
        with (
            zipfile.ZipFile(folder / "arrays.npz", "w", zipfile.ZIP_DEFLATED) as archive,
            archive.open("mu.npy", "w", force_zip64=True) as member,
        ):  # 200 MiB unpacked, ~200 KiB packed
            member.write(b"\x93NUMPY\x01\x00v\x00")
            for _ in range(200):
                member.write(b"0" * (1024 * 1024))
        label = "zip bomb"
    elif kind == 5:
        np.save(folder / "bare.npy", np.zeros(3))
        (folder / "bare.npy").rename(folder / "arrays.npz")
        label = "bare .npy as arrays.npz"
    elif kind == 6:
        with np.load(folder / "arrays.npz") as npz:
            arrays = {k: npz[k] for k in npz.files}
        sigma = arrays["Sigma"].copy()
        sigma[0, 0, 1] += rng.choice([1.0, 1e-3, 1e300])
        if rng.random() < 0.5:
            sigma[0] = -sigma[0]
        arrays["Sigma"] = sigma
        if rng.random() < 0.3:
            arrays["mu"] = np.full_like(arrays["mu"], rng.choice([1e308, -1e308, 1e7]))
        np.savez(folder / "arrays.npz", **arrays)
        label = "bad Sigma or mu"
    elif kind == 7:
        with np.load(folder / "arrays.npz") as npz:
            arrays = {k: npz[k] for k in npz.files}
        name = rng.choice(sorted(arrays))
        arrays[name] = rng.choice(
            [
                np.zeros((10**4,)),
                np.array(["x"]),
                np.zeros(arrays[name].shape, np.complex64),
                arrays[name].astype(np.int64),
                np.zeros((0,)),
            ]
        )
        np.savez(folder / "arrays.npz", **arrays)
        label = f"{name} replaced"
    else:
        map_case(rng, folder)
        label = "hostile map"
    if reseal and kind != 3:
        names = sorted(p.name for p in folder.iterdir() if p.is_file() and p.name != MANIFEST)
        (folder / MANIFEST).write_text(json.dumps(manifest_of(folder, names)), encoding="utf-8")
    return label + (" (resealed)" if reseal else "")


def run_case(call: Callable[[], object], label: str) -> tuple[str, float, str, float]:
    """(outcome, seconds, message, peak MiB): ok, error (a one-line SpcotmhpError) or traceback, and the most
    memory the call itself held above what the process held before it (:func:`case_peak`)."""
    t0 = time.perf_counter()
    with case_peak() as peak:
        try:
            call()
            outcome, message = "ok", ""
        except SpcotmhpError as exc:
            message = str(exc)
            outcome = "error" if message and "\n" not in message and len(message) < 1000 else "traceback"
        except Exception as exc:  # noqa: BLE001 - exactly what the fuzzing looks for
            outcome, message = "traceback", f"{type(exc).__name__}: {exc}"[:300]
    return outcome, time.perf_counter() - t0, f"{label}: {message}"[:400], peak[0]


def _status_mib(key: str) -> float:
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith(key + ":"):
                return int(line.split()[1]) / 1024
    raise OSError(f"no {key} in /proc/self/status")


@contextmanager
def case_peak() -> Iterator[list[float]]:
    """The peak memory (MiB) of the block above the process's resident size when it began, in ``peak[0]`` after
    the block. On Linux the kernel's high-water mark is reset first (``/proc/self/clear_refs`` 5), so C
    allocations (image decoders, numpy) count, and what earlier tests held at their peak does not; elsewhere
    tracemalloc's peak of Python's and numpy's allocations."""
    peak = [0.0]
    try:
        with open("/proc/self/clear_refs", "w") as refs:
            refs.write("5")
        before = _status_mib("VmRSS")
    except OSError:
        before = -1.0
    if before < 0:
        tracemalloc.start()
    try:
        yield peak
    finally:
        if before >= 0:
            peak[0] = _status_mib("VmHWM") - before
        else:
            peak[0] = tracemalloc.get_traced_memory()[1] / 2**20
            tracemalloc.stop()


def main(n: int) -> None:  # pragma: no cover - a command-line report
    import warnings

    from spcotmhp.datasets.loader import load_dataset
    from spcotmhp.datasets.synthetic import generate_environment, write_dataset
    from spcotmhp.learning.supervised import fit_supervised
    from spcotmhp.metric.map_io import load_map
    from spcotmhp.persistence.io import load_model, save_model

    warnings.simplefilter("ignore")
    root = Path(tempfile.mkdtemp())
    data = write_dataset(generate_environment("flat", seed=1, n_rooms=4), root / "template-data")
    model = save_model(fit_supervised(load_dataset(data)), root / "template-model")
    kinds = {
        "map": (lambda r, f: map_case(r, f), lambda f: load_map(f / "map.yaml"), n),
        "dataset": (lambda r, f: dataset_case(r, f, data), lambda f: load_dataset(f), n // 2),
        "model": (lambda r, f: model_case(r, f, model), lambda f: load_model(f), n),
    }
    for kind, (make, load, count) in kinds.items():
        tally, slowest, worst, most = {"ok": 0, "error": 0, "traceback": 0}, 0.0, "", 0.0
        for seed in range(count):
            folder = root / f"{kind}-{seed}"
            folder.mkdir()
            label = make(random.Random(seed), folder)
            outcome, seconds, message, peak = run_case(lambda load=load, folder=folder: load(folder), label)
            tally[outcome] += 1
            most = max(most, peak)
            if seconds > slowest:
                slowest, worst = seconds, label
            if outcome == "traceback":
                print("TRACEBACK", kind, seed, message)
            shutil.rmtree(folder, ignore_errors=True)
        print(f"{kind}: {count} cases {tally}, slowest {slowest:.2f} s ({worst}), largest case peak {most:.0f} MiB")
    shutil.rmtree(root, ignore_errors=True)


if __name__ == "__main__":  # pragma: no cover
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 100)
