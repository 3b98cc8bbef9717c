"""One home for reading untrusted files: bounded sizes, bounded nesting, no code execution, typed one-line errors.

Every reader of a data, map or model file goes through these helpers, so the same guarantees hold everywhere:

* ``read_text``: a UTF-8 text file of at most ``max_bytes`` (the size is checked before reading).
* ``load_yaml``: PyYAML's safe loader without anchors or aliases (no "billion laughs" expansion), at most
  ``MAX_DEPTH`` levels of nesting (no ``RecursionError``) and integers of at most ``MAX_INT_DIGITS`` digits (a
  400-digit integer cannot overflow a float later); only plain YAML types are built, nothing is executed.
* ``load_json`` / ``parse_json``: the same bounds for JSON (``NaN``, ``Infinity`` and numbers beyond a float's
  range such as ``1e400`` refused too).
* ``open_image``: only PGM/PPM, PNG and BMP are decoded (never EPS/PS, which would start Ghostscript), after
  checking from the header, before decoding: a PGM/PPM header (comments included) of at most
  ``MAX_PNM_HEADER_BYTES`` (64 KiB; map_saver writes about 50 bytes), at most ``MAX_PLAIN_PNM_VALUES`` sample
  values in a plain (ASCII) PGM/PPM/PBM (2,000,000: Pillow decodes them in Python), the pixel count against
  ``max_map_pixels()`` (no decompression bomb) and the aspect ratio against ``MAX_MAP_ASPECT`` (1000: a
  corridor 1 km long and 1 m wide at 5 cm cells; a longer strip is not a floor plan, and every per-row step of
  the tools grows with its length); any decoder failure (a corrupt chunk, a truncated file) is one error naming
  the file.
* ``excerpt``: a short quotation of an offending value for messages (never the whole input).

Limits are module constants; the map pixel cap can be changed per process with the environment variable
``SPCOTMHP_MAX_MAP_PIXELS`` (a positive integer).
"""

from __future__ import annotations

import json
import math
import os
import re
import stat
import warnings
from pathlib import Path
from typing import Any, TypeGuard

import numpy as np
import yaml

from spcotmhp.errors import SpcotmhpError

MAX_DEPTH = 32  # nesting levels of a YAML or JSON document
MAX_INT_DIGITS = 30  # digits of an integer in YAML or JSON (int64 has 19)
MAX_NAME_CHARS = 255  # characters of a file name given inside a file (map.yaml's image, model.json's map)
DEFAULT_MAX_MAP_PIXELS = 16_000_000  # width x height of a map image (a 4000 x 4000 map at 0.05 m is 200 m wide)
IMAGE_FORMATS = {"PPM": "PGM/PPM", "PNG": "PNG", "BMP": "BMP"}  # Pillow plugin -> name in messages
EXCERPT_CHARS = 60
IMAGE_BYTES_PER_PIXEL = 8
MAX_PNM_HEADER_BYTES = 64 * 1024
MAX_MAP_ASPECT = 1000
MAX_PLAIN_PNM_VALUES = 2_000_000  # sample values of a plain (ASCII) P1/P2/P3 file: about 0.6 s of Pillow's decoding
PNM_WHITESPACE = b" \t\n\x0b\x0c\r"
IMAGE_EXTRA_BYTES = 1 << 20

ErrorType = type[SpcotmhpError]


def excerpt(value: Any, limit: int = EXCERPT_CHARS) -> str:
    """``repr(value)`` cut to about ``limit`` characters (with the total length when cut), for messages."""
    if isinstance(value, (dict, list, tuple)) and len(value) > 8:
        text = f"{type(value).__name__} of {len(value)} items"
        return text
    try:
        text = repr(value)
    except Exception:  # noqa: BLE001 - a repr that fails is shown by its type only
        return f"<{type(value).__name__}>"
    if len(text) <= limit:
        return text
    return f"{text[:limit]}... ({len(text)} characters)"


def max_map_pixels() -> int:
    """The map image pixel cap: ``SPCOTMHP_MAX_MAP_PIXELS`` when set to a positive integer, else the default."""
    raw = os.environ.get("SPCOTMHP_MAX_MAP_PIXELS", "").strip()
    if raw.isdigit() and 0 < int(raw) < 2**62:
        return int(raw)
    return DEFAULT_MAX_MAP_PIXELS


def max_image_bytes() -> int:
    """The most bytes a map image of ``max_map_pixels()`` pixels takes: ``IMAGE_BYTES_PER_PIXEL`` (8: RGBA at 16
    bits a channel, the widest pixel read_image decodes; a PNG's deflate adds far less than its filter byte
    saves) plus ``IMAGE_EXTRA_BYTES`` (1 MiB) of headers, comments and ancillary chunks."""
    return max_map_pixels() * IMAGE_BYTES_PER_PIXEL + IMAGE_EXTRA_BYTES


def check_file_name(name: Any, where: str, error: ErrorType) -> str:
    """A file name given inside a file: a non-empty string of at most ``MAX_NAME_CHARS`` characters without
    NUL or other control characters (``Path`` would raise ``ValueError`` or ``OSError`` on them)."""
    if not isinstance(name, str) or not name.strip():
        raise error(f"{where} must be a non-empty file name, got {excerpt(name)}")
    if len(name) > MAX_NAME_CHARS:
        raise error(f"{where} is a file name of {len(name)} characters; at most {MAX_NAME_CHARS} are accepted")
    if any(ord(c) < 32 or ord(c) == 127 for c in name):
        raise error(f"{where} must not contain control characters (NUL, newline, ...), got {excerpt(name)}")
    return name


def file_kind(path: Path) -> str | None:
    """What ``path`` is when it is not a regular file, in words for a message ("a symlink to /dev/zero, a
    character device", "a named pipe (FIFO)", "a folder", "a broken symlink to x"); None for a regular file (or
    a symlink to one) and for a path that does not exist. Only ``lstat``/``stat`` are called: a device or a pipe
    is never opened (reading /dev/zero never ends, opening a FIFO blocks)."""
    try:
        link = path.lstat()
    except OSError:
        return None
    target = ""
    if stat.S_ISLNK(link.st_mode):
        try:
            target = f"a symlink to {os.readlink(path)}"
            mode = path.stat().st_mode
        except OSError:
            return f"a broken symlink{target.removeprefix('a symlink')}"
    else:
        mode = link.st_mode
    kinds = (
        (stat.S_ISDIR, "a folder"),
        (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"),
        (stat.S_ISFIFO, "a named pipe (FIFO)"),
        (stat.S_ISSOCK, "a socket"),
    )
    if stat.S_ISREG(mode):
        return None
    kind = next((name for test, name in kinds if test(mode)), "not a regular file")
    return f"{target}, {kind}" if target else kind


def require_regular_file(path: Path, what: str, error: ErrorType) -> None:
    """``error`` saying what ``path`` is (:func:`file_kind`) when it exists but is not a regular file."""
    kind = file_kind(path)
    if kind is not None:
        raise error(f"{what} {path} is {kind}, not a regular file")


def read_text(path: Path, max_bytes: int, what: str, error: ErrorType) -> str:
    """The UTF-8 text of ``path`` (a regular file of at most ``max_bytes``)."""
    try:
        size = path.stat().st_size
        require_regular_file(path, what, error)
        if size > max_bytes:
            raise error(f"{what} {path} is {size} bytes; at most {max_bytes} are accepted")
        with path.open("rb") as handle:
            data = handle.read(max_bytes + 1)
    except FileNotFoundError:
        raise error(f"{what} {path} does not exist") from None
    except OSError as exc:
        raise error(f"cannot read {what} {path}: {exc.strerror or exc}") from None
    if len(data) > max_bytes:
        raise error(f"{what} {path} is over {max_bytes} bytes; at most {max_bytes} are accepted")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise error(f"{what} {path} is not UTF-8 text ({exc.reason} at byte {exc.start})") from None


# ---- YAML ---------------------------------------------------------------------------------------------------
class _BoundedLoader(yaml.SafeLoader):
    """SafeLoader refusing anchors and aliases, nesting deeper than MAX_DEPTH and integers over MAX_INT_DIGITS."""

    _depth = 0

    def compose_node(self, parent: Any, index: Any) -> Any:
        event = self.peek_event()
        if isinstance(event, yaml.AliasEvent) or getattr(event, "anchor", None) is not None:
            raise _Refused("YAML anchors and aliases (&name, *name) are not accepted", event.start_mark)
        self._depth += 1
        try:
            if self._depth > MAX_DEPTH:
                raise _Refused(f"nested deeper than {MAX_DEPTH} levels", event.start_mark)
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1

    def construct_mapping(self, node: Any, deep: bool = False) -> Any:
        """A mapping whose keys are each given once: PyYAML keeps the last of two equal keys silently, other
        readers (yaml-cpp, ROS 2's parameter parser) the first or an error, so a file that says a value twice
        is ambiguous, and which one a robot's body or a map took must not depend on the reader."""
        if isinstance(node, yaml.MappingNode):
            seen: dict[tuple[str, str], int] = {}
            for key_node, _ in node.value:
                if not isinstance(key_node, yaml.ScalarNode) or key_node.tag == "tag:yaml.org,2002:merge":
                    continue
                key = (key_node.tag, key_node.value)
                if key in seen:
                    first = seen[key]
                    raise _Refused(
                        f"the key {excerpt(key_node.value)} is given twice (lines {first + 1} and "
                        f"{key_node.start_mark.line + 1}); give each key once",
                        key_node.start_mark,
                    )
                seen[key] = key_node.start_mark.line
        return super().construct_mapping(node, deep)

    def construct_yaml_int(self, node: Any) -> int:
        digits = sum(c.isdigit() for c in str(node.value))
        if digits > MAX_INT_DIGITS:
            raise _Refused(f"an integer of {digits} digits is too large (at most {MAX_INT_DIGITS})", node.start_mark)
        return super().construct_yaml_int(node)


_BoundedLoader.add_constructor("tag:yaml.org,2002:int", _BoundedLoader.construct_yaml_int)
# YAML 1.2's floats with an exponent and no dot or no exponent sign (1e-1, 5e2, 1.5e3): PyYAML's YAML 1.1 rule
# reads them as strings, while yaml-cpp (map_server) and ROS 2's parameter parser read numbers
_BoundedLoader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9][0-9_]*(?:\.[0-9_]*)?|\.[0-9_]+)[eE][-+]?[0-9]+$"),
    list("-+0123456789."),
)


class _Refused(Exception):
    def __init__(self, reason: str, mark: Any) -> None:
        super().__init__(reason)
        self.reason, self.mark = reason, mark


def load_yaml(path: Path, max_bytes: int, what: str, error: ErrorType) -> Any:
    """Parse a YAML file under the module's bounds; any problem is ``error`` naming the file (and line)."""
    text = read_text(path, max_bytes, what, error)
    try:
        return yaml.load(text, Loader=_BoundedLoader)  # a SafeLoader subclass: plain types only
    except _Refused as exc:
        line = f" (line {exc.mark.line + 1})" if exc.mark is not None else ""
        raise error(f"{what} {path}{line}: {exc.reason}") from None
    except (yaml.YAMLError, ValueError, TypeError, OverflowError, RecursionError) as exc:
        reason = " ".join(str(exc).split())
        raise error(f"{what} {path} does not parse: {reason[:200]}") from None


# ---- JSON ---------------------------------------------------------------------------------------------------
_JSON_STRING = re.compile(r'"(?:[^"\\]|\\.)*"', re.DOTALL)


def json_depth(text: str) -> int:
    """The deepest nesting of brackets and braces in a JSON text, not counting those inside strings."""
    skeleton = re.sub(r"[^\[\]{}]", "", _JSON_STRING.sub("", text))
    if not skeleton:
        return 0
    codes = np.frombuffer(skeleton.encode("ascii"), dtype=np.uint8)
    steps = np.where((codes == ord("[")) | (codes == ord("{")), 1, -1)
    return int(np.cumsum(steps).max())


def _json_int(text: str) -> int:
    if len(text.lstrip("-")) > MAX_INT_DIGITS:
        raise ValueError(f"an integer of {len(text.lstrip('-'))} digits is too large (at most {MAX_INT_DIGITS})")
    return int(text)


def _json_float(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise ValueError(f"the number {excerpt(text, 30)} is too large for a float")
    return value


def _json_constant(name: str) -> float:
    raise ValueError(f"{name} is not a number JSON accepts (use a finite number)")


def parse_json(text: str, where: str, error: ErrorType) -> Any:
    """Parse JSON text under the module's bounds (depth, integer size, no NaN/Infinity)."""
    depth = json_depth(text)
    if depth > MAX_DEPTH:
        raise error(f"{where} is nested {depth} levels deep; at most {MAX_DEPTH} are accepted")
    try:
        return json.loads(text, parse_int=_json_int, parse_float=_json_float, parse_constant=_json_constant)
    except json.JSONDecodeError as exc:
        raise error(f"{where} is not valid JSON: {exc.msg} (line {exc.lineno} column {exc.colno})") from None
    except (ValueError, RecursionError) as exc:
        raise error(f"{where} is not accepted: {str(exc)[:200]}") from None


def load_json(path: Path, max_bytes: int, what: str, error: ErrorType) -> Any:
    """Parse a JSON file under the module's bounds; any problem is ``error`` naming the file."""
    return parse_json(read_text(path, max_bytes, what, error), f"{what} {path}", error)


def finite_number(value: object) -> TypeGuard[int | float | np.integer | np.floating]:
    """A real number (not a boolean) that is finite as a float; huge integers are not (no OverflowError)."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        return False
    try:
        return math.isfinite(float(value))
    except OverflowError:
        return False


# ---- images -------------------------------------------------------------------------------------------------
def open_image(path: Path, error: ErrorType, max_pixels: int | None = None) -> Any:
    """A decoded PIL image of a PGM/PPM, PNG or BMP file with at most ``max_pixels`` (default
    ``max_map_pixels()``) pixels; the caller closes it. Every failure is ``error`` naming the file."""
    from PIL import Image

    cap = max_map_pixels() if max_pixels is None else max_pixels
    accepted = ", ".join(dict.fromkeys(IMAGE_FORMATS.values()))
    try:
        require_regular_file(path, "map image", error)
        if not path.is_file():
            raise error(f"map image {path} does not exist")
        check_pnm_header(path, error)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)
            img = Image.open(path, formats=tuple(IMAGE_FORMATS))
    except SpcotmhpError:
        raise
    except Image.DecompressionBombError:
        raise error(
            f"map image {path} has more than {cap} pixels (the cap; set SPCOTMHP_MAX_MAP_PIXELS to raise it)"
        ) from None
    except Exception as exc:  # noqa: BLE001 - Pillow's decoders raise many types (OSError, SyntaxError, ...)
        raise error(f"map image {path} cannot be read as {accepted}: {_reason(exc)}") from None
    try:
        width, height = img.size
        if width * height > cap:
            raise error(
                f"map image {path} is {width} x {height} = {width * height} pixels, over the cap of {cap} "
                "(set SPCOTMHP_MAX_MAP_PIXELS to raise it)"
            )
        if width < 1 or height < 1:
            raise error(f"map image {path} is {width} x {height} pixels; a map needs at least one pixel")
        if max(width, height) > MAX_MAP_ASPECT * min(width, height):
            raise error(
                f"map image {path} is {width} x {height} pixels, longer than {MAX_MAP_ASPECT} times its width or "
                f"height; a map's aspect ratio must be at most {MAX_MAP_ASPECT}:1"
            )
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)
            img.load()
    except SpcotmhpError:
        img.close()
        raise
    except Exception as exc:  # noqa: BLE001 - as above: a corrupt chunk is a SyntaxError, a short file an OSError
        img.close()
        raise error(f"map image {path} cannot be read as {accepted}: {_reason(exc)}") from None
    return img


def check_pnm_header(path: Path, error: ErrorType) -> None:
    """A PGM/PPM/PBM file's header (magic, width, height and maxval, with any comments) must end within
    ``MAX_PNM_HEADER_BYTES``; read with one bounded read, before Pillow's byte-by-byte parser sees the file.
    A plain (ASCII: P1, P2, P3) file may hold at most ``MAX_PLAIN_PNM_VALUES`` sample values (Pillow decodes
    them in Python, about 0.3 s a million: a plain PGM at the pixel cap took 5 s of CPU). Files of other
    formats, and headers that do not parse, are left to the decoder."""
    try:
        with path.open("rb") as handle:
            head = handle.read(MAX_PNM_HEADER_BYTES + 1)
    except OSError as exc:
        raise error(f"cannot read map image {path}: {exc.strerror or exc}") from None
    if head[:1] != b"P" or head[1:2] not in b"0123456fy" or len(head) < 2:
        return
    tokens = _pnm_header_tokens(head, 2 if head[:2] in (b"P1", b"P4") else 3)
    if tokens is None and len(head) > MAX_PNM_HEADER_BYTES:
        raise error(
            f"map image {path}: its PGM/PPM header (with comments) is longer than {MAX_PNM_HEADER_BYTES} bytes; "
            f"at most {MAX_PNM_HEADER_BYTES} are accepted"
        )
    if tokens is None or head[:2] not in (b"P1", b"P2", b"P3"):
        return
    if not all(t.isdigit() and len(t) <= 20 for t in tokens[:2]):
        return  # not a size the decoder accepts: it refuses the file
    width, height = (int(t) for t in tokens[:2])
    values = width * height * (3 if head[:2] == b"P3" else 1)
    if values > MAX_PLAIN_PNM_VALUES:
        raise error(
            f"map image {path} is a plain (ASCII) {head[:2].decode()} file of {width} x {height} pixels, "
            f"{values} sample values; a plain PNM file may hold at most {MAX_PLAIN_PNM_VALUES} (save larger maps "
            "as binary PGM (P5) or PNG, as map_saver does)"
        )


def _pnm_header_tokens(head: bytes, fields: int) -> list[bytes] | None:
    """The ``fields`` tokens after the magic number of a PNM header (comments skipped), or None when they do not
    all end within ``MAX_PNM_HEADER_BYTES`` of ``head``."""
    tokens: list[bytes] = []
    at = next((i for i in range(min(len(head), 7)) if head[i] in PNM_WHITESPACE), 6)
    while len(tokens) < fields and at < min(len(head), MAX_PNM_HEADER_BYTES):
        if head[at] in PNM_WHITESPACE:
            at += 1
        elif head[at] == ord("#"):
            ends = [i for i in (head.find(b"\n", at), head.find(b"\r", at)) if i >= 0]
            at = min(ends) if ends else len(head)
        else:
            begin = at
            while at < len(head) and head[at] not in PNM_WHITESPACE and head[at] != ord("#"):
                at += 1
            if at >= len(head) and len(head) > MAX_PNM_HEADER_BYTES:
                return None  # the token runs past the bound
            tokens.append(head[begin:at])
    return tokens if len(tokens) == fields else None


def _reason(exc: BaseException) -> str:
    text = " ".join(str(exc).split()) or type(exc).__name__
    return text[:200]
