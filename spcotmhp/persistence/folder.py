"""The model folder as a unit on disk: confined files, a checksum manifest, bounded arrays, atomic replacement.

A model folder (written by :func:`spcotmhp.persistence.io.save_model`) holds model.json, arrays.npz, usually
map.yaml + map.pgm, and ``manifest.json``::

    {"format": "spcotmhp-model-manifest", "format_version": 2,
     "files": {"model.json": {"bytes": 1234, "sha256": "..."}, "arrays.npz": {...}, ...}}

* Writing (:func:`write_folder`): every file is written into a fresh hidden sibling folder, the manifest last,
  and the folder is then swapped into place (:func:`spcotmhp.safe_write.swap_folder`). Until that swap the
  previous model stays whole and loadable; after it the new one is. An interrupted save leaves at most a
  hidden ``.NAME.new-*`` folder beside it, never a mixture.
* Reading: each listed file must be a regular file inside the folder (a symlink out of the folder is refused)
  with the listed size (:func:`read_manifest`, a stat), at most as large as a model of its sizes can need
  (:func:`check_sizes`; the bounds: ``spcotmhp.persistence.model_checks.file_bound``), and only then is it hashed
  against the listed SHA-256 (:func:`verify_digests`), so a torn, altered or inflated folder is a ModelError
  naming the file, and an 8 GiB sparse file is refused without reading it.
* Arrays (:func:`read_npz`): arrays.npz is opened as a zip archive without numpy's loader: each member must be
  a known ``NAME.npy`` stored or deflated, its uncompressed size no larger than its expected shape needs
  (checked before decompressing: no zip bomb), its ``.npy`` header (read with ``allow_pickle``-free parsing)
  of an accepted dtype and exactly the expected shape; only then is its data read. Nothing is unpickled.
"""

from __future__ import annotations

import hashlib
import json
import zipfile
import zlib
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path

import numpy as np

from spcotmhp.errors import ModelError
from spcotmhp.safe_read import excerpt, load_json
from spcotmhp.safe_write import build_folder

MANIFEST = "manifest.json"
MANIFEST_FORMAT = "spcotmhp-model-manifest"
MANIFEST_VERSION = 2
MAX_MANIFEST_BYTES = 64 * 1024
MAX_HEADER_BYTES = 4096  # a .npy header (dict of descr, fortran_order, shape) is under 200 bytes
MEMBER_RECORD_BYTES = 1024  # a member's local header and central directory entry (each 30-46 bytes + name + extras)
ARCHIVE_RECORD_BYTES = 1024  # the end of central directory records (22 bytes, 98 with zip64)
CHUNK = 1 << 20


# ---- confinement and the manifest --------------------------------------------------------------------------
def inside(root: Path, name: object, what: str) -> Path:
    """``root / name`` when ``name`` is a plain file name of the folder ``root`` whose target (symlinks seen
    through) lies inside ``root``; ModelError otherwise."""
    if not isinstance(name, (str, Path)) or not str(name).strip() or len(str(name)) > 255 or "\0" in str(name):
        raise ModelError(f"{root / 'model.json'}: {what} must be a file name, got {excerpt(name)}")
    path = root / name
    try:
        real = path.resolve()
        inner = real.is_relative_to(root.resolve())
    except (OSError, RuntimeError, ValueError):
        inner = False
    if not inner:
        shown = f"{excerpt(str(name))}" + (" (a symbolic link)" if path.is_symlink() else "")
        raise ModelError(
            f"{root}: {what} must be a file inside the model folder {root}, got {shown}, which leads outside it"
        )
    return path


def file_digest(path: Path) -> tuple[int, str]:
    """(size in bytes, SHA-256 hex digest) of a file, read in 1 MiB chunks."""
    digest, size = hashlib.sha256(), 0
    with path.open("rb") as handle:
        while chunk := handle.read(CHUNK):
            digest.update(chunk)
            size += len(chunk)
    return size, digest.hexdigest()


def manifest_of(folder: Path, names: list[str]) -> dict:
    """The manifest of the files ``names`` of ``folder``."""
    files = {}
    for name in names:
        size, sha = file_digest(folder / name)
        files[name] = {"bytes": size, "sha256": sha}
    return {"format": MANIFEST_FORMAT, "format_version": MANIFEST_VERSION, "files": files}


def read_manifest(root: Path, skip: tuple[str, ...] = ()) -> dict[str, tuple[int, str]] | None:
    """name -> (bytes, SHA-256) of ``root``'s manifest.json (None without one), after checking that every
    listed file is a regular file inside the folder whose size is the listed one: a stat, nothing is read, so a
    file grown by gigabytes is refused at once. Files named in ``skip`` (checked by their own reader: the saved
    planning graph, :mod:`spcotmhp.planning.graph_store`) are confined but may be missing or of another size."""
    path = root / MANIFEST
    if not path.exists() and not path.is_symlink():
        return None
    inside(root, MANIFEST, MANIFEST)
    doc = load_json(path, MAX_MANIFEST_BYTES, "model manifest", ModelError)
    files = doc.get("files") if isinstance(doc, dict) else None
    if not isinstance(doc, dict) or doc.get("format") != MANIFEST_FORMAT or not isinstance(files, dict) or not files:
        raise ModelError(f'{path} is not a spcotmhp model manifest (format {MANIFEST_FORMAT!r} with "files")')
    if doc.get("format_version") != MANIFEST_VERSION:
        raise ModelError(
            f"{path} has format version {excerpt(doc.get('format_version'))}; this spcotmhp reads "
            f"version {MANIFEST_VERSION}"
        )
    entries = {}
    for name, entry in files.items():
        target = inside(root, name, f"the manifest's file {excerpt(name)}")
        ok = isinstance(entry, dict) and isinstance(entry.get("bytes"), int) and isinstance(entry.get("sha256"), str)
        if not ok:
            raise ModelError(f'{path}: the entry of {excerpt(name)} must be {{"bytes": int, "sha256": hex}}')
        if name in skip:
            entries[name] = (entry["bytes"], entry["sha256"])
            continue
        if not target.is_file():
            raise ModelError(
                f"{root}: {name} is listed in {MANIFEST} but missing (a torn or altered model "
                "folder: save the model again)"
            )
        size = _size(target)
        if size != entry["bytes"]:
            raise ModelError(
                f"{target} is {size} bytes, but {MANIFEST} lists {entry['bytes']}: the model folder is torn or "
                "altered; save the model again"
            )
        entries[name] = (size, entry["sha256"])
    return entries


def check_sizes(root: Path, names: Iterable[str], bound: Callable[[str], tuple[int, str]]) -> None:
    """Each file ``names`` of ``root`` that exists at most ``bound(name)`` = (bytes, why) long (``why`` says
    what the bound comes from); checked with a stat before the file is hashed or read."""
    for name in names:
        target = root / name
        if not target.is_file():
            continue
        size, (limit, why) = _size(target), bound(name)
        if size > limit:
            raise ModelError(
                f"{target} is {size} bytes; " + (f"{why} {limit} bytes" if why else f"at most {limit} are accepted")
            )


def verify_digests(root: Path, entries: Mapping[str, tuple[int, str]], names: Iterable[str]) -> None:
    """The SHA-256 of each file ``names`` (listed in ``entries``, sizes already checked) against the manifest."""
    for name in names:
        target = root / name
        try:
            size, sha = file_digest(target)
        except OSError as exc:
            raise ModelError(f"cannot read {target}: {exc.strerror or exc}") from None
        if size != entries[name][0] or sha != entries[name][1]:
            raise ModelError(
                f"{target} does not match its checksum in {MANIFEST} ({size} bytes, listed "
                f"{entries[name][0]}): the model folder is torn or was altered; save the model again"
            )


def npz_bound(specs: Mapping[str, tuple[tuple[int, ...], str]]) -> int:
    """The most bytes an .npz of the arrays ``specs`` (name -> shape) takes: 8 bytes a number (float64 or
    int64, the widest dtype read_npz accepts) plus 1 % (a deflated member of random bytes grows by far less),
    and per member its .npy header (at most MAX_HEADER_BYTES) and its zip records (at most MEMBER_RECORD_BYTES,
    zip64 extras and the name included)."""
    total = ARCHIVE_RECORD_BYTES
    for shape, _ in specs.values():
        total += int(np.prod(shape, dtype=np.int64)) * 8 * 101 // 100 + MAX_HEADER_BYTES + MEMBER_RECORD_BYTES
    return total


def _size(path: Path) -> int:
    try:
        return path.stat().st_size
    except OSError as exc:
        raise ModelError(f"cannot read {path}: {exc.strerror or exc}") from None


# ---- writing -----------------------------------------------------------------------------------------------
def write_folder(target: Path, writers: Mapping[str, Callable[[Path], object]], known: tuple[str, ...]) -> Path:
    """Build the folder ``target`` atomically: ``writers[name](path)`` writes each file into a fresh sibling
    folder, then the manifest, then the sibling replaces ``target``.

    An existing ``target`` must be a model folder (holding model.json) whose files are all among ``known``
    (the files save_model writes, plus the manifest): a folder with anything else (a dataset, the user's own
    files) is never replaced. Raises ModelError naming the folder and the reason."""
    check_replaceable(target, known)

    def fill(staging: Path) -> None:
        for name, write in writers.items():
            write(staging / name)
        manifest = manifest_of(staging, [p.name for p in sorted(staging.iterdir()) if p.is_file()])
        (staging / MANIFEST).write_text(json.dumps(manifest, indent=1), encoding="utf-8")

    build_folder(target, fill, ModelError, f"save the model to {target}")
    return target


def check_replaceable(target: Path, known: tuple[str, ...], advice: str = "choose an empty or new folder") -> None:
    """ModelError unless ``target`` is absent, an empty folder, or a model folder of only ``known`` files;
    ``advice`` ends the message about a folder holding other files."""
    if target.is_symlink() or (target.exists() and not target.is_dir()):
        raise ModelError(f"cannot save the model to {target}: it exists and is not a folder")
    if not target.exists():
        return
    try:
        present = sorted(p.name for p in target.iterdir())
    except OSError as exc:
        raise ModelError(f"cannot save the model to {target}: {exc.strerror or exc}") from None
    if not present:
        return
    others = [name for name in present if name not in known + (MANIFEST,)]
    if "model.json" not in present or others:
        listed = ", ".join(others[:5]) + (" ..." if len(others) > 5 else "")
        raise ModelError(
            f"cannot save the model to {target}: the folder holds files that are not a model's "
            f"({listed or ', '.join(present[:5])}); {advice}"
        )


# ---- arrays ------------------------------------------------------------------------------------------------
def read_npz(path: Path, specs: Mapping[str, tuple[tuple[int, ...], str]], optional: tuple[str, ...]) -> dict:
    """The arrays of ``path`` (module docstring): ``specs[name] = (shape, kinds)`` with ``kinds`` the accepted
    numpy dtype kinds ("f" floating, "b" boolean, "fiu" numbers). Names in ``optional`` may be absent."""
    if not path.is_file():
        raise ModelError(f"{path} is missing (a model folder holds model.json and arrays.npz)")
    try:
        with zipfile.ZipFile(path) as archive:
            infos = archive.infolist()
            members = _members(path, infos, specs, optional)
            return {name: _read_member(path, archive, info, *specs[name]) for name, info in members.items()}
    except ModelError:
        raise
    except (
        zipfile.BadZipFile,
        zlib.error,
        NotImplementedError,
        ValueError,
        EOFError,
        OSError,
        RuntimeError,
        KeyError,
        TypeError,
    ) as exc:
        reason = " ".join(str(exc).split())[:160] or type(exc).__name__
        raise ModelError(f"{path} cannot be read as a numpy .npz archive of plain arrays: {reason}") from None


def _members(path: Path, infos: list, specs: Mapping, optional: tuple[str, ...]) -> dict:
    members = {}
    for info in infos:
        name = info.filename.removesuffix(".npy")
        if name not in specs or not info.filename.endswith(".npy"):
            raise ModelError(
                f"{path} holds an unknown member {excerpt(info.filename)} (known arrays: {', '.join(specs)})"
            )
        if name in members:
            raise ModelError(f"{path} holds {info.filename} twice")
        if info.compress_type not in (zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED):
            raise ModelError(f"{path}: {info.filename} uses an unsupported compression (stored or deflated only)")
        shape, _ = specs[name]
        limit = int(np.prod(shape, dtype=np.int64)) * 8 + MAX_HEADER_BYTES
        if info.file_size > limit:
            raise ModelError(
                f"{path}: {info.filename} unpacks to {info.file_size} bytes, more than its shape "
                f"{shape} needs ({limit} bytes at most)"
            )
        members[name] = info
    missing = [name for name in specs if name not in members and name not in optional]
    if missing:
        raise ModelError(f"{path} lacks the array(s) {', '.join(missing)}")
    return members


def _read_member(
    path: Path, archive: zipfile.ZipFile, info: zipfile.ZipInfo, shape: tuple[int, ...], kinds: str
) -> np.ndarray:
    fmt = np.lib.format
    with archive.open(info) as handle:
        version = fmt.read_magic(handle)
        if version == (1, 0):
            got, fortran, dtype = fmt.read_array_header_1_0(handle, max_header_size=MAX_HEADER_BYTES)
        elif version == (2, 0):
            got, fortran, dtype = fmt.read_array_header_2_0(handle, max_header_size=MAX_HEADER_BYTES)
        else:
            raise ModelError(f"{path}: {info.filename} has .npy format version {version}; 1.0 or 2.0 expected")
        where = f"{path}: {info.filename.removesuffix('.npy')}"
        if dtype.hasobject or dtype.kind not in kinds or dtype.itemsize > 8:
            raise ModelError(f"{where} has dtype {dtype}; expected {_kinds(kinds)}")
        if tuple(got) != tuple(shape):
            raise ModelError(f"{where} has shape {tuple(got)}, but model.json needs {tuple(shape)}")
        count = int(np.prod(shape, dtype=np.int64))
        data = handle.read(count * dtype.itemsize)
        if len(data) != count * dtype.itemsize or handle.read(1):
            raise ModelError(f"{where}: the data does not match its header's shape {tuple(shape)} (a torn file)")
    return np.frombuffer(data, dtype=dtype).reshape(shape, order="F" if fortran else "C").copy()


def _kinds(kinds: str) -> str:
    names = {"f": "floating-point numbers", "b": "booleans", "i": "integers", "u": "integers"}
    return " or ".join(dict.fromkeys(names[k] for k in kinds))
