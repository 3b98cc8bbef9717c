"""Read and write ROS map_server maps (YAML + image) exactly as Nav2's ``nav2_map_server/map_io.cpp`` does.

Loading (``load_map``): the YAML names ``image`` (relative to the YAML), ``resolution``, ``origin``
[x, y, yaw], ``negate``, ``occupied_thresh``, ``free_thresh`` and optionally ``mode`` (trinary, the default;
scale; raw). Per pixel, ``shade`` in [0, 1] is the mean of the colour channels (R, G, B; a grey image counts
its grey value three times); in trinary mode an image with an alpha channel averages the alpha in too
(R, G, B, A), as Nav2 and ROS 1's map_server do. ``occ = shade`` if negate else ``1 - shade``, then

* trinary: ``occ > occupied_thresh`` -> 100, ``occ < free_thresh`` -> 0, else -1;
* scale: a pixel that is not fully opaque -> -1, else as trinary, with values in between
  ``rint((occ - free_thresh) / (occupied_thresh - free_thresh) * 100)``;
* raw: ``round(shade * 255)``, kept where it lies in 0..100, else -1.

Image row 0 is the top of the map; OccupancyGrid row 0 is the row at the origin, so rows are flipped.

Saving (``save_map``) follows Nav2's map_saver: trinary writes free 254, occupied 0, unknown 205 (8-bit
grey); scale writes grey (100 - value) / 100 with unknown transparent (RGBA PNG); raw writes the value itself
as the grey level and unknown as 255. The YAML gets image, mode, resolution, origin (at full precision, where
Nav2 keeps 3 digits), ``negate: 0`` and the thresholds.
"""

from __future__ import annotations

import re
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml
from PIL import Image

from spcotmhp.errors import MapError
from spcotmhp.metric.maps import OccupancyMap
from spcotmhp.safe_read import check_file_name, excerpt, finite_number, load_yaml, open_image
from spcotmhp.safe_write import atomic_write

MODES = ("trinary", "scale", "raw")
MAX_YAML_BYTES = 64 * 1024  # a map_server YAML is a few hundred bytes
MAX_ORIGIN_M = 1e6  # |origin x, y| in metres (a map 1000 km from its frame is a mistake)
MIN_RESOLUTION, MAX_RESOLUTION = 1e-4, 1e3  # metres per cell
IMAGE_FORMATS = ("pgm", "png", "bmp")
# grey levels that Nav2's map_saver writes in trinary mode
SAVE_FREE, SAVE_OCCUPIED, SAVE_UNKNOWN = 254, 0, 205


@dataclass(frozen=True)
class MapMetadata:
    """The validated contents of a map_server YAML file."""

    image: Path
    resolution: float
    origin: tuple[float, float, float]
    negate: bool
    occupied_thresh: float
    free_thresh: float
    mode: str


# ----------------------------------------------------------------------------------------------- loading


def load_map(yaml_path: str | Path) -> OccupancyMap:
    """Load a ROS map_server map (YAML + PGM/PNG/BMP image) into an ``OccupancyMap`` as Nav2 does.

    Only axis-aligned maps are supported: a non-zero origin yaw raises ``MapError``, as does any missing or
    malformed key, a missing or unreadable image, an unknown mode or inconsistent thresholds.
    """
    meta = read_map_yaml(yaml_path)
    rgb, alpha, maxval = read_image(meta.image)
    data = pixels_to_grid(rgb, alpha, maxval, meta.mode, meta.negate, meta.occupied_thresh, meta.free_thresh)
    return OccupancyMap(
        data=data,
        resolution=meta.resolution,
        origin=meta.origin,
        mode=meta.mode,
        negate=meta.negate,
        occupied_thresh=meta.occupied_thresh,
        free_thresh=meta.free_thresh,
        source=Path(yaml_path),
    )


def read_map_yaml(yaml_path: str | Path) -> MapMetadata:
    """Parse and validate a map_server YAML file; the image path is resolved (see ``resolve_image_path``).

    The file is read with :func:`spcotmhp.safe_read.load_yaml` (at most 64 KiB, no anchors or aliases, bounded
    nesting and integers); numbers must be finite, ``resolution`` within 1e-4..1e3 m and ``|origin|`` within
    1e6 m; ``image`` a file name of at most 255 characters without control characters."""
    path = Path(yaml_path)
    if not path.is_file():
        raise MapError(f"map YAML {path} does not exist")
    doc = load_yaml(path, MAX_YAML_BYTES, "map YAML", MapError)
    if not isinstance(doc, dict):
        raise MapError(f"map YAML {path} must be a mapping of keys (image, resolution, origin, ...)")

    def need(key: str) -> object:
        if key not in doc or doc[key] is None:
            raise MapError(f"map YAML {path}: required key '{key}' is missing")
        return doc[key]

    image = check_file_name(need("image"), f"map YAML {path}: key 'image'", MapError)
    resolution = _number(path, "resolution", need("resolution"))
    if not MIN_RESOLUTION <= resolution <= MAX_RESOLUTION:
        raise MapError(
            f"map YAML {path}: key 'resolution' must be a number of metres per cell in "
            f"{MIN_RESOLUTION:g}..{MAX_RESOLUTION:g}, got {excerpt(resolution)}"
        )
    origin = need("origin")
    if not isinstance(origin, (list, tuple)) or len(origin) != 3:
        raise MapError(f"map YAML {path}: key 'origin' must be a list of 3 numbers [x, y, yaw], got {excerpt(origin)}")
    ox, oy, yaw = (_number(path, "origin", v) for v in origin)
    if max(abs(ox), abs(oy)) > MAX_ORIGIN_M:
        raise MapError(f"map YAML {path}: origin x and y must lie within +-{MAX_ORIGIN_M:g} m, got [{ox:g}, {oy:g}]")
    if yaw != 0.0:
        raise MapError(
            f"map YAML {path}: origin yaw {yaw!r} is not supported; only axis-aligned maps (yaw 0) are accepted"
        )
    negate = need("negate")
    if isinstance(negate, bool):
        negate_flag = negate
    elif isinstance(negate, int) and negate in (0, 1):
        negate_flag = bool(negate)
    else:
        raise MapError(f"map YAML {path}: key 'negate' must be 0, 1, true or false, got {excerpt(negate)}")
    occupied = _number(path, "occupied_thresh", need("occupied_thresh"))
    free = _number(path, "free_thresh", need("free_thresh"))
    _check_thresholds(f"map YAML {path}", occupied, free)
    mode = doc.get("mode", "trinary")
    if not isinstance(mode, str) or mode.lower() not in MODES:
        raise MapError(f"map YAML {path}: key 'mode' must be one of {', '.join(MODES)}, got {excerpt(mode)}")
    return MapMetadata(
        image=resolve_image_path(path, image),
        resolution=resolution,
        origin=(ox, oy, 0.0),
        negate=negate_flag,
        occupied_thresh=occupied,
        free_thresh=free,
        mode=mode.lower(),
    )


def resolve_image_path(yaml_path: Path, image: str) -> Path:
    """The image file a YAML names: relative names are taken beside the YAML (as Nav2 does); an absolute
    path that does not exist falls back to the file of that name beside the YAML (a map from elsewhere)."""
    named = Path(image)
    if not named.is_absolute():
        return yaml_path.parent / named
    if named.exists():
        return named
    beside = yaml_path.parent / named.name
    if beside.exists():
        return beside
    raise MapError(
        f"map YAML {yaml_path}: image {excerpt(str(named))} does not exist, nor does {beside.name} beside the YAML"
    )


def read_image(path: Path) -> tuple[np.ndarray, np.ndarray | None, int]:
    """Read a map image as (channels, alpha, maxval) in image row order: ``channels`` int (H, W, 3) with
    R, G, B (a grey image repeats its grey value: a read-only view, not a copy), ``alpha`` int (H, W) or None
    without alpha, both in 0..maxval (255, or 65535 for 16-bit images); int32, but an 8-bit grey image's
    channels are its own uint8 bytes.

    Only PGM/PPM, PNG and BMP files are decoded, with at most ``safe_read.max_map_pixels()`` pixels, an aspect
    ratio of at most ``safe_read.MAX_MAP_ASPECT`` and a PGM/PPM header of at most 64 KiB, all checked before
    decoding (:func:`spcotmhp.safe_read.open_image`); anything else is a MapError naming the file."""
    with open_image(path, MapError) as img:
        return _image_channels(path, img)


def _image_channels(path: Path, img: Image.Image) -> tuple[np.ndarray, np.ndarray | None, int]:
    mode = img.mode
    if mode == "1":
        img, mode = img.convert("L"), "L"
    elif mode in ("P", "PA"):
        transparent = mode == "PA" or "transparency" in img.info
        img = img.convert("RGBA" if transparent else "RGB")
        mode = img.mode
    elif mode in ("CMYK", "YCbCr", "LAB", "HSV", "RGBX"):
        img, mode = img.convert("RGB"), "RGB"
    elif mode in ("La", "RGBa"):
        img = img.convert(mode.upper()[:-1] + "A")
        mode = img.mode
    if mode == "L":  # 8-bit grey: its own bytes (pixels_to_grid reads them through a table; no int32 copy)
        a = np.asarray(img)
        return np.broadcast_to(a[:, :, None], a.shape + (3,)), None, 255
    a = np.asarray(img).astype(np.int32)  # int32 holds four 16-bit channels' sum; a quarter of int64's memory
    if mode.startswith("I;16") or mode == "I":
        if a.size and (a.min() < 0 or a.max() > 65535):
            raise MapError(f"map image {path}: 32-bit images are not supported (values beyond 16 bits)")
        return np.broadcast_to(a[:, :, None], a.shape + (3,)), None, 65535
    if mode == "LA":
        return np.broadcast_to(a[:, :, :1], a.shape[:2] + (3,)), a[:, :, 1], 255
    if mode == "RGB":
        return a, None, 255
    if mode == "RGBA":
        return a[:, :, :3], a[:, :, 3], 255
    raise MapError(f"map image {path}: unsupported pixel format {mode} (use 8/16-bit grey, RGB or RGBA)")


def pixels_to_grid(
    rgb: np.ndarray,
    alpha: np.ndarray | None,
    maxval: int,
    mode: str,
    negate: bool,
    occupied_thresh: float,
    free_thresh: float,
) -> np.ndarray:
    """Nav2's per-pixel rule (module docstring) on integer image-order pixels (``read_image``) -> int8 grid in
    OccupancyGrid order. Like Nav2, the channel sum is exact and ``shade = (sum / n) / maxval``.

    A grey image without alpha (``rgb`` a broadcast of one channel) is mapped through a table of the rule's
    value for each of the maxval + 1 shades, computed by this same rule: the same grid, without float arrays
    of the image's size (a 4000 x 4000 map took seconds)."""
    if alpha is None and rgb.ndim == 3 and rgb.strides[2] == 0 and rgb.size > 3 * (maxval + 1):
        shades = np.arange(maxval + 1, dtype=np.int32)
        table = pixels_to_grid(
            np.broadcast_to(shades[None, :, None], (1, maxval + 1, 3)),
            None,
            maxval,
            mode,
            negate,
            occupied_thresh,
            free_thresh,
        )[0]
        return np.ascontiguousarray(table[rgb[::-1, :, 0]])
    if mode == "trinary" and alpha is not None:
        shade = ((rgb.sum(axis=2) + alpha) / 4.0) / maxval
    else:
        shade = (rgb.sum(axis=2) / 3.0) / maxval
    occ = shade if negate else 1.0 - shade
    if mode == "raw":
        value = np.floor(shade * 255.0 + 0.5)  # std::round: halves away from zero
        grid = np.where((value >= 0) & (value <= 100), value, -1)
    elif mode in ("trinary", "scale"):
        if mode == "scale":
            between = np.rint((occ - free_thresh) / (occupied_thresh - free_thresh) * 100.0)
        else:
            between = np.full(occ.shape, -1.0)
        grid = np.where(occupied_thresh < occ, 100, np.where(occ < free_thresh, 0, between))
        if mode == "scale" and alpha is not None:
            grid = np.where(alpha != maxval, -1, grid)
    else:
        raise MapError(f"unknown map mode {mode!r}; accepted: {', '.join(MODES)}")
    return np.ascontiguousarray(grid[::-1].astype(np.int8))


# ----------------------------------------------------------------------------------------------- saving


def save_map(
    occ_map: OccupancyMap,
    path_prefix_or_yaml: str | Path,
    mode: str = "trinary",
    image_format: str | None = None,
    occupied_thresh: float | None = None,
    free_thresh: float | None = None,
) -> Path:
    """Write ``occ_map`` as Nav2's map_saver does: ``PREFIX.yaml`` and ``PREFIX.<image_format>``.

    ``image_format`` defaults to png in scale mode (it needs transparency) and pgm otherwise; thresholds
    default to the map's own. Returns the YAML path. Warns when loading the files back would not give the
    same grid (e.g. trinary with free_thresh above 50/255, so that unknown grey 205 reads back as free).
    """
    mode = mode.lower()
    if mode not in MODES:
        raise MapError(f"cannot save map: unknown mode {mode!r}; accepted: {', '.join(MODES)}")
    fmt = (image_format or ("png" if mode == "scale" else "pgm")).lower().lstrip(".")
    if fmt not in IMAGE_FORMATS:
        raise MapError(f"cannot save map: image format {fmt!r} is not one of {', '.join(IMAGE_FORMATS)}")
    if mode == "scale" and fmt != "png":
        raise MapError(f"cannot save map: scale mode needs transparency for unknown cells, use png, not {fmt}")
    occupied = occ_map.occupied_thresh if occupied_thresh is None else float(occupied_thresh)
    free = occ_map.free_thresh if free_thresh is None else float(free_thresh)
    _check_thresholds("cannot save map", occupied, free)
    if occ_map.origin[2] != 0.0:
        raise MapError(f"cannot save map: origin yaw {occ_map.origin[2]!r} is not supported (yaw must be 0)")

    target = Path(path_prefix_or_yaml)
    prefix = target.with_suffix("") if target.suffix.lower() in (".yaml", ".yml") else target
    yaml_path = prefix.parent / (prefix.name + ".yaml")
    image_path = prefix.parent / (prefix.name + "." + fmt)

    pixels = grid_to_pixels(occ_map.data, mode, occupied, free)
    image = Image.fromarray(pixels, mode="RGBA" if pixels.ndim == 3 else "L")
    meta = {
        "image": image_path.name,
        "mode": mode,
        "resolution": float(occ_map.resolution),
        "origin": [float(occ_map.origin[0]), float(occ_map.origin[1]), 0.0],
        "negate": 0,
        "occupied_thresh": occupied,
        "free_thresh": free,
    }
    # each file is written atomically (a temporary renamed into place): a reader never sees half an image
    atomic_write(image_path, lambda tmp: image.save(tmp, format="PPM" if fmt == "pgm" else fmt.upper()), MapError)
    text = yaml.safe_dump(meta, sort_keys=False, default_flow_style=None)
    atomic_write(yaml_path, lambda tmp: tmp.write_text(text, encoding="utf-8"), MapError)

    _warn_if_changed(occ_map, pixels, yaml_path, mode, occupied, free)
    return yaml_path


def _warn_if_changed(
    occ_map: OccupancyMap, pixels: np.ndarray, yaml_path: Path, mode: str, occupied: float, free: float
) -> None:
    """Warn when the saved pixels would load back as another grid than ``occ_map`` (map_saver's lossy modes)."""
    if pixels.ndim == 3:
        ints = pixels.astype(np.int64)
        back = pixels_to_grid(ints[..., :3], ints[..., 3], 255, mode, False, occupied, free)
    else:  # grey: one channel broadcast, read through pixels_to_grid's table (no image-sized copies)
        back = pixels_to_grid(np.broadcast_to(pixels[:, :, None], (*pixels.shape, 3)), None, 255, mode, False,
                              occupied, free)  # fmt: skip
    changed = int(np.count_nonzero(back != occ_map.data))
    if changed:
        warnings.warn(
            f"saved map {yaml_path} will load back with {changed} cells changed (map_saver's {mode} mode "
            f"with thresholds {occupied}/{free}); use mode='raw' for an exact copy",
            stacklevel=3,
        )


def grid_to_pixels(data: np.ndarray, mode: str, occupied_thresh: float, free_thresh: float) -> np.ndarray:
    """Nav2 map_saver's pixels for an OccupancyGrid-order grid: uint8 (H, W) grey, or (H, W, 4) RGBA in scale
    mode, in image row order (top row first). An int8 grid in trinary or raw mode is mapped through a table of
    this rule's pixel for each of the 256 values (the same pixels, without int64 arrays of the map's size)."""
    data = np.asarray(data)
    if data.dtype == np.int8 and data.size > 256 and mode in ("trinary", "raw"):
        table = grid_to_pixels(np.arange(-128, 128, dtype=np.int8)[None, :], mode, occupied_thresh, free_thresh)[0]
        return table[data[::-1].view(np.uint8) ^ np.uint8(128)]  # value v at index v + 128
    cells = np.asarray(data, dtype=np.int16)[::-1]
    unknown = (cells < 0) | (cells > 100)
    if mode == "trinary":
        free_int = int(np.rint(free_thresh * 100.0))
        occupied_int = int(np.rint(occupied_thresh * 100.0))
        grey = np.select([cells <= free_int, cells >= occupied_int], [SAVE_FREE, SAVE_OCCUPIED], SAVE_UNKNOWN)
        return np.where(unknown, SAVE_UNKNOWN, grey).astype(np.uint8)
    if mode == "raw":
        return np.where(unknown, 255, cells).astype(np.uint8)
    if mode == "scale":
        grey = _magick_grey((100.0 - cells) / 100.0)
        rgba = np.empty(cells.shape + (4,), dtype=np.uint8)
        rgba[..., :3] = np.where(unknown, _magick_grey(np.array(0.5)), grey)[..., None]
        rgba[..., 3] = np.where(unknown, 0, 255)
        return rgba
    raise MapError(f"unknown map mode {mode!r}; accepted: {', '.join(MODES)}")


def _magick_grey(level: np.ndarray) -> np.ndarray:
    """8-bit grey that (Q16) GraphicsMagick writes for ``ColorGray(level)``: truncate to 16 bits, round."""
    quantum = np.floor(np.clip(level, 0.0, 1.0) * 65535.0)
    return ((quantum + 128) // 257).astype(np.uint8)


# ----------------------------------------------------------------------------------------------- helpers


_DECIMAL = re.compile(r"[-+]?(\.[0-9]+|[0-9]+(\.[0-9]*)?)([eE][-+]?[0-9]+)?[ \t]*")
"""A decimal number as yaml-cpp's ``as<double>()`` (C++ stream extraction) reads it: PyYAML's YAML 1.1 resolver
leaves exponent forms without a dot (``5e-2``, ``1e308``) as strings, which Nav2's map_io reads as numbers."""


def _number(path: Path, key: str, value: object) -> float:
    """The finite number of ``key``: a YAML number, or a string yaml-cpp reads as one (``_DECIMAL``)."""
    number = float(value) if isinstance(value, str) and _DECIMAL.fullmatch(value) else value
    if not finite_number(number):  # '1e400' reads as inf: refused, as yaml-cpp refuses it
        raise MapError(f"map YAML {path}: key '{key}' must be a finite number, got {excerpt(value)}")
    return float(number)


def _check_thresholds(where: str, occupied: float, free: float) -> None:
    if not (0.0 <= free < occupied <= 1.0):
        raise MapError(
            f"{where}: thresholds must satisfy 0 <= free_thresh < occupied_thresh <= 1, "
            f"got free_thresh {free!r}, occupied_thresh {occupied!r}"
        )
