"""graph.npz: a planning graph's arrays in one uncompressed .npz, read by mapping, each array checked by a checksum.

A 16-megapixel map's graph holds hundreds of megabytes of per-cell arrays and local fields, of which a plan reads
a few paths' worth. So the arrays are stored uncompressed (``np.savez``: zip members ``NAME.npy``, stored) and
mapped read-only (``np.memmap``), never read whole: a plan command's memory holds the pages its plans touch, and
loading costs no decompression.

Checks, before any array is mapped (the shapes come from graph.json, already checked against the map and the
model by :mod:`spcotmhp.planning.graph_arrays`): every member a known, stored ``NAME.npy``; its ``.npy`` header
(parsed without ``allow_pickle``) of an accepted dtype in the machine's byte order, in C order, and exactly the
expected shape; its data inside the file
(so a header claiming a huge shape is refused, and nothing is allocated for it); then its 64-bit checksum
(:func:`checksum`, listed in graph.json, itself checked by SHA-256 against the model folder's manifest) over the
bytes read in chunks. The checksum runs at memory speed where SHA-256 of the whole file would take seconds per
command on a big map; it finds a torn or damaged file, and a deliberately altered one can do no more than any
altered model (every index is checked before use: :func:`~spcotmhp.planning.graph_arrays.check_values`).
"""

from __future__ import annotations

import mmap
import struct
import zipfile
from collections.abc import Mapping
from pathlib import Path
from typing import BinaryIO

import numpy as np
from numba import njit

from spcotmhp.errors import ModelError
from spcotmhp.safe_read import excerpt

CHUNK = 8 << 20  # bytes a checksum pass reads at once (a multiple of 32)
MAX_HEADER_BYTES = 4096
MAPPED_BYTES = 1 << 20  # arrays at least this large are mapped; smaller ones are read into memory
_LOCAL_HEADER = struct.Struct("<4sHHHHHIIIHH")  # a zip member's local file header (30 bytes)


@njit(cache=True)
def _mix(state: np.ndarray, words: np.ndarray) -> None:  # pragma: no cover
    """Fold 64-bit words into the 4-lane state (multiply-xorshift; lanes give the CPU independent chains)."""
    prime, shift = np.uint64(0x9E3779B97F4A7C15), np.uint64(29)
    s0, s1, s2, s3 = state[0], state[1], state[2], state[3]
    for i in range(0, words.shape[0], 4):
        x0 = (s0 ^ words[i]) * prime
        x1 = (s1 ^ words[i + 1]) * prime
        x2 = (s2 ^ words[i + 2]) * prime
        x3 = (s3 ^ words[i + 3]) * prime
        s0, s1, s2, s3 = x0 ^ (x0 >> shift), x1 ^ (x1 >> shift), x2 ^ (x2 >> shift), x3 ^ (x3 >> shift)
    state[0], state[1], state[2], state[3] = s0, s1, s2, s3


BLOCKS = "per-node"
"""graph.json's checksum of the portal graph's tree codes: one checksum a node's block, checked when a plan first
reads the block (:class:`~spcotmhp.planning.hierarchy.TerritoryFields`): a 16-megapixel map's codes take
gigabytes, of which a plan reads a few nodes'."""


def checksum(read: BinaryIO | np.ndarray, size: int) -> str:
    """The 64-bit checksum (hex) of ``size`` bytes: of a file object from its position, read in chunks (so the
    bytes never all sit in memory), or of a uint8 array."""
    return "".join(f"{int(v):016x}" for v in checksum_words(read, size))


def checksum_words(read: BinaryIO | np.ndarray, size: int) -> np.ndarray:
    """:func:`checksum` as its four 64-bit words."""
    state = np.array([1, 2, 3, 4], dtype=np.uint64) * np.uint64(0x94D049BB133111EB)
    done = 0
    if isinstance(read, np.ndarray):  # its whole 32-byte blocks in place (no copy), then the tail as below
        done = size // 32 * 32
        _mix(state, read[:done].view(np.uint64))
    buffer = np.empty((min(CHUNK, size - done) + 31) // 32 * 32, dtype=np.uint8)
    while done < size:
        n = min(CHUNK, size - done)
        if isinstance(read, np.ndarray):
            buffer[:n] = read[done : done + n]
        elif read.readinto(buffer[:n].data) != n:  # type: ignore[attr-defined]
            raise ModelError(f"the file ends before its {size} bytes")
        padded = (n + 31) // 32 * 32
        buffer[n:padded] = 0
        _mix(state, buffer[:padded].view(np.uint64))
        done += n
    _mix(state, np.array([size, 0, 0, 0], dtype=np.uint64))
    return state


def _mapped_checksum(handle: BinaryIO, start: int, nbytes: int) -> str:
    """:func:`checksum` of the file's ``nbytes`` bytes from ``start``, read through a mapping of its own (no copy
    into a buffer; the pages leave the process's memory when it is closed)."""
    if nbytes == 0:
        return checksum(np.empty(0, dtype=np.uint8), 0)
    base = start - start % mmap.ALLOCATIONGRANULARITY
    with mmap.mmap(handle.fileno(), start + nbytes - base, access=mmap.ACCESS_READ, offset=base) as mapped:
        data = np.frombuffer(mapped, dtype=np.uint8, count=nbytes, offset=start - base)
        words = checksum(data, nbytes)
        del data  # no view of the mapping may outlive it
    return words


def array_checksum(array: np.ndarray) -> str:
    """:func:`checksum` of an array's bytes in C order (what np.savez writes after the header)."""
    data = np.ascontiguousarray(array)
    return checksum(data.reshape(-1).view(np.uint8), data.nbytes)


def read_mapped(
    path: Path, specs: Mapping[str, tuple[tuple[int, ...], str]], sums: Mapping[str, str], optional: tuple[str, ...]
) -> dict[str, np.ndarray]:
    """The arrays of the stored .npz ``path`` (module docstring): ``specs[name] = (shape, kinds)``, ``sums[name]``
    the checksum; large arrays mapped read-only, small ones read. ModelError names the file and the array."""
    arrays: dict[str, np.ndarray] = {}
    try:
        with path.open("rb") as handle:
            size = handle.seek(0, 2)
            with zipfile.ZipFile(handle) as archive:
                infos = archive.infolist()
                names = [info.filename.removesuffix(".npy") for info in infos]
                for name, info in zip(names, infos, strict=True):
                    if name not in specs or not info.filename.endswith(".npy") or names.count(name) > 1:
                        raise ModelError(f"{path} holds an unexpected member {excerpt(info.filename)}")
                    if info.compress_type != zipfile.ZIP_STORED:
                        raise ModelError(f"{path}: {info.filename} is compressed; a graph's arrays are stored")
                    arrays[name] = _member(path, handle, size, archive, info, *specs[name], sums.get(name))
    except (zipfile.BadZipFile, ValueError, OSError, EOFError, struct.error) as exc:
        reason = " ".join(str(exc).split())[:160] or type(exc).__name__
        raise ModelError(f"{path} cannot be read as an .npz archive of plain arrays: {reason}") from None
    missing = [name for name in specs if name not in arrays and name not in optional]
    if missing:
        raise ModelError(f"{path} lacks the array(s) {', '.join(missing[:5])}")
    return arrays


def _member(
    path: Path,
    handle: BinaryIO,
    size: int,
    archive: zipfile.ZipFile,
    info: zipfile.ZipInfo,
    shape: tuple[int, ...],
    kinds: str,
    expected: str | None,
) -> np.ndarray:
    where = f"{path}: {info.filename.removesuffix('.npy')}"
    fmt = np.lib.format
    with archive.open(info) as member:
        version = fmt.read_magic(member)
        if version not in ((1, 0), (2, 0)):
            raise ModelError(f"{where} has .npy format version {version}; 1.0 or 2.0 expected")
        read_header = fmt.read_array_header_1_0 if version == (1, 0) else fmt.read_array_header_2_0
        got, fortran, dtype = read_header(member, max_header_size=MAX_HEADER_BYTES)
        header_bytes = member.tell()
    if info.filename.endswith("hier.fcode.npy") and dtype != np.int8:
        raise ModelError(f"{where} has dtype {dtype}; the tree codes are int8")
    if dtype.hasobject or dtype.kind not in kinds or dtype.itemsize > 8 or (dtype.kind == "f" and dtype.itemsize < 4):
        raise ModelError(f"{where} has dtype {dtype}; expected numbers of kind {kinds}")
    if not dtype.isnative or fortran:  # np.savez writes neither; the compiled search takes neither
        raise ModelError(
            f"{where} is stored {'in Fortran order' if fortran else f'as {dtype.str}'}; np.savez's "
            "native byte order and C order are expected"
        )
    if tuple(got) != tuple(shape):
        raise ModelError(f"{where} has shape {tuple(got)}, but graph.json needs {tuple(shape)}")
    nbytes = int(np.prod(shape, dtype=np.int64)) * dtype.itemsize
    handle.seek(info.header_offset)
    local = _LOCAL_HEADER.unpack(handle.read(_LOCAL_HEADER.size))
    start = info.header_offset + _LOCAL_HEADER.size + local[9] + local[10] + header_bytes
    if local[0] != b"PK\x03\x04" or info.file_size != header_bytes + nbytes or start + nbytes > size:
        raise ModelError(f"{where}: its data ({nbytes} bytes for shape {tuple(shape)}) is not in the file")
    if expected is None:
        raise ModelError(f"{where} has no checksum in graph.json")
    handle.seek(start)
    if expected == BLOCKS and not info.filename.endswith("hier.fcode.npy"):
        raise ModelError(f"{where}: only the tree codes are checked block by block")
    if expected != BLOCKS and _mapped_checksum(handle, start, nbytes) != expected:
        raise ModelError(f"{where} does not match its checksum in graph.json (a torn or damaged file)")
    if nbytes == 0:
        return np.zeros(shape, dtype=dtype)
    mapped = np.memmap(handle, dtype=dtype, mode="r", offset=start, shape=shape, order="C")
    return np.array(mapped) if nbytes < MAPPED_BYTES else mapped
