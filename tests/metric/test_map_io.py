"""ROS map_server YAML + image reading and writing (Nav2 map_io semantics)."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from PIL import Image

from spcotmhp.errors import MapError
from spcotmhp.metric.map_io import load_map, read_map_yaml, save_map
from spcotmhp.metric.maps import OccupancyMap

DATA = Path(__file__).resolve().parents[2] / "spcotmhp" / "data"
HOMES = sorted((DATA / "sigverse-3ldk").glob("3LDK_*"))
BASE = {
    "resolution": 0.1,
    "origin": [-1.0, 2.0, 0.0],
    "negate": 0,
    "occupied_thresh": 0.65,
    "free_thresh": 0.196,
}


def write_map(tmp_path: Path, pixels: np.ndarray, name: str = "map.png", img_mode: str | None = None, **keys) -> Path:
    """Write ``pixels`` (image row order) with Pillow and a YAML naming it; ``keys`` override BASE."""
    Image.fromarray(pixels, mode=img_mode).save(tmp_path / name)
    meta = {"image": name, **BASE, **keys}
    path = tmp_path / "map.yaml"
    path.write_text(yaml.safe_dump(meta))
    return path


def write_yaml(tmp_path: Path, meta: dict | str) -> Path:
    path = tmp_path / "bad.yaml"
    path.write_text(meta if isinstance(meta, str) else yaml.safe_dump(meta))
    return path


def assert_same_map(a: OccupancyMap, b: OccupancyMap) -> None:
    np.testing.assert_array_equal(a.data, b.data)
    assert a.data.dtype == b.data.dtype == np.int8
    assert a.resolution == b.resolution
    assert a.origin == b.origin


# ------------------------------------------------------------------------------------------- bundled maps


@pytest.mark.parametrize("home", HOMES, ids=[h.name for h in HOMES])
def test_bundled_sigverse_maps(home: Path) -> None:
    m = load_map(home / "map.yaml")
    assert m.shape == (192, 192)
    assert m.resolution == 0.1
    assert m.origin == (-10.0, -10.0, 0.0)
    assert (m.negate, m.mode, m.occupied_thresh, m.free_thresh) == (False, "trinary", 0.65, 0.196)
    pixels = np.asarray(Image.open(home / "map.pgm"))
    # image row 0 is the top; grid row 0 is the bottom image row. 254 free, 0 occupied, 205 unknown.
    expected = np.select([pixels == 254, pixels == 0], [0, 100], -1)[::-1]
    np.testing.assert_array_equal(m.data, expected)
    assert m.source == home / "map.yaml"


def test_bundled_albert_b_map() -> None:
    m = load_map(DATA / "albert-b" / "map.yaml")
    assert (m.width, m.height) == (1184, 800)
    assert m.resolution == 0.05
    assert m.origin == (-30.0, -20.0, 0.0)
    assert (int(m.free.sum()), int(m.occupied.sum()), int(m.unknown.sum())) == (84498, 6302, 856400)


def test_bundled_map_orientation_first_image_row_is_last_grid_row() -> None:
    pixels = np.asarray(Image.open(HOMES[0] / "map.pgm"))
    m = load_map(HOMES[0] / "map.yaml")
    top = np.where(pixels[0] == 254, 0, np.where(pixels[0] == 0, 100, -1))
    np.testing.assert_array_equal(m.data[-1], top)


# ------------------------------------------------------------------------------------------- pixel rules


def test_trinary_thresholds_by_hand(tmp_path: Path) -> None:
    # occ = 1 - v/255: 0 -> 1.0, 89 -> 0.651, 90 -> 0.647, 205 -> 0.196078 (>= 0.196: unknown), 206 -> 0.192
    row = np.array([[0, 89, 90, 205, 206, 255]], dtype=np.uint8)
    m = load_map(write_map(tmp_path, row))
    np.testing.assert_array_equal(m.data, [[100, 100, -1, -1, 0, 0]])


def test_trinary_threshold_comparisons_are_strict(tmp_path: Path) -> None:
    # v = 102: occ = 1 - 102/255 = 0.6 exactly as doubles; occupied needs occ > 0.6, free needs occ < 0.6
    row = np.array([[102]], dtype=np.uint8)
    assert load_map(write_map(tmp_path, row, occupied_thresh=0.6, free_thresh=0.1)).data[0, 0] == -1
    assert load_map(write_map(tmp_path, row, occupied_thresh=0.9, free_thresh=0.6)).data[0, 0] == -1


def test_negate_swaps_black_and_white(tmp_path: Path) -> None:
    row = np.array([[0, 128, 255]], dtype=np.uint8)
    cases = ((1, [0, -1, 100]), (True, [0, -1, 100]), (0, [100, -1, 0]), (False, [100, -1, 0]))
    for negate, expected in cases:
        m = load_map(write_map(tmp_path, row, negate=negate))
        assert m.negate is bool(negate)
        np.testing.assert_array_equal(m.data, [expected])


def test_rows_are_flipped(tmp_path: Path) -> None:
    col = np.array([[0], [255], [205]], dtype=np.uint8)  # top black, middle white, bottom grey
    m = load_map(write_map(tmp_path, col))
    np.testing.assert_array_equal(m.data[:, 0], [-1, 0, 100])


def test_rgb_shade_is_the_channel_mean_not_luminance(tmp_path: Path) -> None:
    # red and blue: mean 85 -> occ 0.667 -> occupied; yellow and cyan: mean 170 -> occ 0.333 -> unknown
    # (a luminance conversion would make yellow, 226, free)
    rgb = np.array([[[255, 0, 0], [255, 255, 0], [0, 0, 255], [0, 255, 255], [254, 254, 254]]], dtype=np.uint8)
    m = load_map(write_map(tmp_path, rgb))
    np.testing.assert_array_equal(m.data, [[100, -1, 100, -1, 0]])


def test_trinary_averages_alpha_in(tmp_path: Path) -> None:
    # white but fully transparent: (255*3 + 0)/4 = 191.25 -> occ 0.25 -> unknown; opaque white -> free;
    # black transparent: 0 -> occupied
    rgba = np.array([[[255, 255, 255, 0], [255, 255, 255, 255], [0, 0, 0, 0]]], dtype=np.uint8)
    m = load_map(write_map(tmp_path, rgba))
    np.testing.assert_array_equal(m.data, [[-1, 0, 100]])


def test_grey_alpha_counts_grey_three_times(tmp_path: Path) -> None:
    # LA (230, 0): Nav2 averages R, G, B, A = (3*230 + 0)/4 = 172.5 -> occ 0.3235 -> unknown.
    # (A mean of grey and alpha alone, 115, would give occ 0.55 -> also unknown; (250, 100) separates them:
    # (750 + 100)/4 = 212.5 -> occ 0.167 -> free, whereas (250 + 100)/2 = 175 -> occ 0.31 -> unknown.)
    la = np.array([[[230, 0], [250, 100]]], dtype=np.uint8)
    m = load_map(write_map(tmp_path, la, img_mode="LA"))
    np.testing.assert_array_equal(m.data, [[-1, 0]])


def test_scale_mode(tmp_path: Path) -> None:
    # thresholds free 0.2, occupied 0.8; v = 128: occ = 0.49804 -> rint((0.49804 - 0.2) / 0.6 * 100) = 50;
    # v = 200: occ 0.2157 -> rint(2.61) = 3; transparent or half transparent -> unknown; alpha not averaged in
    rgba = np.array(
        [
            [
                [128, 128, 128, 255],
                [200, 200, 200, 255],
                [0, 0, 0, 255],
                [255, 255, 255, 255],
                [128, 128, 128, 0],
                [128, 128, 128, 254],
            ]
        ],
        dtype=np.uint8,
    )
    m = load_map(write_map(tmp_path, rgba, mode="scale", occupied_thresh=0.8, free_thresh=0.2))
    np.testing.assert_array_equal(m.data, [[50, 3, 100, 0, -1, -1]])
    assert m.mode == "scale"


def test_scale_mode_without_alpha_is_opaque(tmp_path: Path) -> None:
    grey = np.array([[128, 0, 255]], dtype=np.uint8)
    m = load_map(write_map(tmp_path, grey, name="m.pgm", mode="Scale", occupied_thresh=0.8, free_thresh=0.2))
    np.testing.assert_array_equal(m.data, [[50, 100, 0]])


def test_raw_mode(tmp_path: Path) -> None:
    grey = np.array([[0, 1, 50, 100, 101, 255]], dtype=np.uint8)
    for negate in (0, 1):  # raw ignores negate, as Nav2 does
        m = load_map(write_map(tmp_path, grey, name="m.pgm", mode="raw", negate=negate))
        np.testing.assert_array_equal(m.data, [[0, 1, 50, 100, -1, -1]])


def test_sixteen_bit_pgm(tmp_path: Path) -> None:
    # 16-bit grey: shade = v / 65535; 13107 -> occ 0.8 occupied; 52428 -> occ 0.2 unknown;
    # 52700 -> occ 0.1959 free
    # (52700 lies between the 8-bit levels 205 and 206: 16-bit precision is kept)
    grey = np.array([[0, 13107, 52428, 52700, 65535]], dtype=np.uint16)
    path = write_map(tmp_path, grey, name="m16.pgm")
    assert (tmp_path / "m16.pgm").read_bytes().startswith(b"P5\n5 1\n65535\n")
    np.testing.assert_array_equal(load_map(path).data, [[100, 100, -1, 0, 0]])


def test_sixteen_bit_png(tmp_path: Path) -> None:
    grey = np.array([[0, 65535]], dtype=np.uint16)
    np.testing.assert_array_equal(load_map(write_map(tmp_path, grey, name="m16.png")).data, [[100, 0]])


def test_bmp_and_bilevel_and_palette_images(tmp_path: Path) -> None:
    grey = np.array([[0, 205, 254]], dtype=np.uint8)
    np.testing.assert_array_equal(load_map(write_map(tmp_path, grey, name="m.bmp")).data, [[100, -1, 0]])
    Image.fromarray(np.array([[0, 255]], dtype=np.uint8)).convert("1").save(tmp_path / "bw.png")
    (tmp_path / "bw.yaml").write_text(yaml.safe_dump({"image": "bw.png", **BASE}))
    np.testing.assert_array_equal(load_map(tmp_path / "bw.yaml").data, [[100, 0]])
    pal = Image.fromarray(np.array([[0, 1, 2]], dtype=np.uint8), mode="P")
    pal.putpalette([255, 255, 255, 0, 0, 0, 255, 0, 0] + [0] * 759)
    pal.save(tmp_path / "pal.png")
    (tmp_path / "pal.yaml").write_text(yaml.safe_dump({"image": "pal.png", **BASE}))
    np.testing.assert_array_equal(load_map(tmp_path / "pal.yaml").data, [[0, 100, 100]])


def test_mode_and_image_path_details(tmp_path: Path) -> None:
    (tmp_path / "img").mkdir()
    Image.fromarray(np.array([[0, 254]], dtype=np.uint8)).save(tmp_path / "img" / "m.pgm")
    path = write_yaml(tmp_path, {"image": "img/m.pgm", "mode": "TRINARY", **BASE})
    meta = read_map_yaml(path)
    assert meta.image == tmp_path / "img" / "m.pgm" and meta.mode == "trinary"
    np.testing.assert_array_equal(load_map(path).data, [[100, 0]])


def test_absolute_image_path(tmp_path: Path) -> None:
    Image.fromarray(np.array([[0, 254]], dtype=np.uint8)).save(tmp_path / "m.pgm")
    path = write_yaml(tmp_path, {"image": str(tmp_path / "m.pgm"), **BASE})
    assert read_map_yaml(path).image == tmp_path / "m.pgm"
    # an absolute path from another machine falls back to the file of that name beside the YAML
    path = write_yaml(tmp_path, {"image": "/home/somebody/maps/m.pgm", **BASE})
    assert read_map_yaml(path).image == tmp_path / "m.pgm"
    np.testing.assert_array_equal(load_map(path).data, [[100, 0]])


# ------------------------------------------------------------------------------------------- bad input


def test_missing_yaml(tmp_path: Path) -> None:
    with pytest.raises(MapError, match=r"map YAML .*nothere\.yaml does not exist"):
        load_map(tmp_path / "nothere.yaml")


@pytest.mark.parametrize(
    "text, message",
    [
        ("image: [unclosed\n", "does not parse"),
        ("image: a: b\n", "does not parse"),
        ("- just\n- a list\n", "must be a mapping"),
        ("", "must be a mapping"),
    ],
)
def test_yaml_that_does_not_parse(tmp_path: Path, text: str, message: str) -> None:
    path = write_yaml(tmp_path, text)
    with pytest.raises(MapError, match=message) as info:
        load_map(path)
    assert str(path) in str(info.value)


@pytest.mark.parametrize("key", ["image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh"])
def test_missing_required_key(tmp_path: Path, key: str) -> None:
    meta = {"image": "m.pgm", **BASE}
    del meta[key]
    path = write_yaml(tmp_path, meta)
    with pytest.raises(MapError, match=f"required key '{key}' is missing") as info:
        load_map(path)
    assert str(path) in str(info.value)


@pytest.mark.parametrize(
    "key, value, message",
    [
        ("image", "", "key 'image' must be a non-empty file name"),
        ("image", 12, "key 'image' must be a non-empty file name"),
        ("resolution", 0, r"key 'resolution' must be a number of metres per cell in 0.0001..1000, got 0"),
        ("resolution", -0.05, "key 'resolution' must be a number of metres per cell"),
        ("resolution", "fine", "key 'resolution' must be a finite number, got 'fine'"),
        ("resolution", float("nan"), "key 'resolution' must be a finite number"),
        ("resolution", True, "key 'resolution' must be a finite number"),
        ("origin", [0, 0], r"key 'origin' must be a list of 3 numbers \[x, y, yaw\]"),
        ("origin", "0 0 0", "key 'origin' must be a list of 3 numbers"),
        ("origin", [0, "x", 0], "key 'origin' must be a finite number, got 'x'"),
        ("origin", [0, 0, 0.5], r"origin yaw 0.5 is not supported; only axis-aligned maps \(yaw 0\)"),
        ("negate", 2, "key 'negate' must be 0, 1, true or false, got 2"),
        ("negate", "maybe", "key 'negate' must be 0, 1, true or false"),
        (
            "occupied_thresh",
            0.1,
            r"0 <= free_thresh < occupied_thresh <= 1, got free_thresh 0.196, occupied_thresh 0.1",
        ),
        ("occupied_thresh", 1.5, "free_thresh < occupied_thresh <= 1"),
        ("free_thresh", -0.1, "0 <= free_thresh"),
        ("free_thresh", 0.65, "free_thresh < occupied_thresh"),
        ("free_thresh", "low", "key 'free_thresh' must be a finite number"),
        ("mode", "binary", "key 'mode' must be one of trinary, scale, raw, got 'binary'"),
        ("mode", 3, "key 'mode' must be one of trinary, scale, raw"),
    ],
)
def test_invalid_key(tmp_path: Path, key: str, value: object, message: str) -> None:
    Image.fromarray(np.zeros((2, 2), dtype=np.uint8)).save(tmp_path / "m.pgm")
    path = write_yaml(tmp_path, {"image": "m.pgm", **BASE, key: value})
    with pytest.raises(MapError, match=message) as info:
        load_map(path)
    assert str(path) in str(info.value)


NAV2_YAML = """image: m.pgm
mode: trinary
resolution: {resolution}
origin: [{ox}, {oy}, 0]
negate: 0
occupied_thresh: {occupied}
free_thresh: {free}
"""


@pytest.mark.parametrize(
    "keys, resolution, origin",
    [
        ({"resolution": "5e-2"}, 0.05, (0.0, 0.0)),
        ({"resolution": "1E-1", "ox": "-1e1", "oy": "+2.5e0"}, 0.1, (-10.0, 2.5)),
        ({"resolution": "1e-4", "ox": "1e5"}, 1e-4, (1e5, 0.0)),
        ({"occupied": "65e-2", "free": "1.96e-1"}, 0.05, (0.0, 0.0)),
        ({"resolution": "'5e-2'"}, 0.05, (0.0, 0.0)),  # yaml-cpp converts a quoted scalar too
        ({"resolution": "5.", "ox": ".5"}, 5.0, (0.5, 0.0)),
    ],
)
def test_exponent_numbers_as_nav2_reads_them(tmp_path: Path, keys: dict, resolution: float, origin) -> None:
    """Audit item 7: PyYAML's YAML 1.1 resolver reads 5e-2 (no dot) as a string; Nav2's map_io (yaml-cpp
    as<double>) reads it as 0.05. The numeric keys accept it."""
    Image.fromarray(np.zeros((2, 2), dtype=np.uint8)).save(tmp_path / "m.pgm")
    fields = {"resolution": "0.05", "ox": "0", "oy": "0", "occupied": "0.65", "free": "0.196", **keys}
    (tmp_path / "map.yaml").write_text(NAV2_YAML.format(**fields))
    m = load_map(tmp_path / "map.yaml")
    assert m.resolution == resolution and m.origin[:2] == origin


@pytest.mark.parametrize(
    "keys, message",
    [
        ({"resolution": "1e-9"}, r"resolution' must be a number of metres per cell in 0.0001..1000, got 1e-09"),
        ({"ox": "1e308"}, r"origin x and y must lie within \+-1e\+06 m"),
        ({"ox": "1e400"}, r"key 'origin' must be a finite number, got inf"),  # YAML 1.2: a float, too large
        ({"resolution": ".nan"}, r"key 'resolution' must be a finite number, got nan"),
        ({"resolution": ".inf"}, r"key 'resolution' must be a finite number, got inf"),
        ({"resolution": "nan"}, r"key 'resolution' must be a finite number, got 'nan'"),
        ({"resolution": "5e"}, r"key 'resolution' must be a finite number, got '5e'"),
        ({"free": "1e-1e"}, r"key 'free_thresh' must be a finite number, got '1e-1e'"),
    ],
)
def test_exponent_numbers_still_checked(tmp_path: Path, keys: dict, message: str) -> None:
    Image.fromarray(np.zeros((2, 2), dtype=np.uint8)).save(tmp_path / "m.pgm")
    fields = {"resolution": "0.05", "ox": "0", "oy": "0", "occupied": "0.65", "free": "0.196", **keys}
    (tmp_path / "map.yaml").write_text(NAV2_YAML.format(**fields))
    with pytest.raises(MapError, match=message):
        load_map(tmp_path / "map.yaml")


def test_missing_image(tmp_path: Path) -> None:
    path = write_yaml(tmp_path, {"image": "gone.pgm", **BASE})
    with pytest.raises(MapError, match=r"map image .*gone\.pgm does not exist"):
        load_map(path)
    path = write_yaml(tmp_path, {"image": "/elsewhere/gone.pgm", **BASE})
    with pytest.raises(MapError, match=r"image '/elsewhere/gone\.pgm' does not exist, nor does gone\.pgm"):
        load_map(path)


def test_unreadable_image(tmp_path: Path) -> None:
    (tmp_path / "m.pgm").write_text("this is not an image")
    with pytest.raises(MapError, match=r"map image .*m\.pgm cannot be read"):
        load_map(write_yaml(tmp_path, {"image": "m.pgm", **BASE}))
    (tmp_path / "t.pgm").write_bytes(b"P5\n4 4\n255\n\x00\x01")  # truncated pixel data
    with pytest.raises(MapError, match=r"map image .*t\.pgm cannot be read"):
        load_map(write_yaml(tmp_path, {"image": "t.pgm", **BASE}))


def test_unsupported_pixel_formats(tmp_path: Path) -> None:
    (tmp_path / "f.pfm").write_bytes(b"Pf\n1 1\n-1.0\n" + np.float32(0.5).tobytes())  # float grey, read by PPM
    with pytest.raises(MapError, match=r"f\.pfm: unsupported pixel format F"):
        load_map(write_yaml(tmp_path, {"image": "f.pfm", **BASE}))
    Image.fromarray(np.array([[70000]], dtype=np.int32), mode="I").save(tmp_path / "i.tif")
    with pytest.raises(MapError, match=r"i\.tif cannot be read as PGM/PPM, PNG, BMP"):  # TIFF is not accepted
        load_map(write_yaml(tmp_path, {"image": "i.tif", **BASE}))


# ------------------------------------------------------------------------------------------- saving


@pytest.mark.parametrize("home", [*HOMES, DATA / "albert-b"], ids=[*[h.name for h in HOMES], "albert-b"])
def test_save_reproduces_the_bundled_pgm(tmp_path: Path, home: Path) -> None:
    m = load_map(home / "map.yaml")
    yaml_path = save_map(m, tmp_path / "copy")
    assert yaml_path == tmp_path / "copy.yaml"
    np.testing.assert_array_equal(
        np.asarray(Image.open(tmp_path / "copy.pgm")), np.asarray(Image.open(home / "map.pgm"))
    )
    assert (tmp_path / "copy.pgm").read_bytes()[:2] == b"P5"
    assert_same_map(load_map(yaml_path), m)


def test_saved_yaml_content(tmp_path: Path) -> None:
    m = OccupancyMap(np.array([[0, 100], [-1, 0]], dtype=np.int8), 0.05, (-12.345678901, 3.5, 0.0))
    yaml_path = save_map(m, tmp_path / "out.yaml")
    text = yaml_path.read_text()
    assert list(yaml.safe_load(text)) == [
        "image",
        "mode",
        "resolution",
        "origin",
        "negate",
        "occupied_thresh",
        "free_thresh",
    ]
    assert yaml.safe_load(text) == {
        "image": "out.pgm",
        "mode": "trinary",
        "resolution": 0.05,
        "origin": [-12.345678901, 3.5, 0.0],
        "negate": 0,
        "occupied_thresh": 0.65,
        "free_thresh": 0.196,
    }
    assert "origin: [-12.345678901, 3.5, 0.0]" in text
    # image row 0 is the top = grid's last row: [-1, 0] -> 205, 254; then [0, 100] -> 254, 0
    np.testing.assert_array_equal(np.asarray(Image.open(tmp_path / "out.pgm")), [[205, 254], [254, 0]])


def test_save_thresholds_override_and_trinary_levels(tmp_path: Path) -> None:
    # free_thresh 0.1 -> 10, occupied 0.6 -> 60: 10 -> 254, 11..59 -> 205, 60 -> 0
    m = OccupancyMap(np.array([[10, 11, 59, 60, 100, -1]], dtype=np.int8), 0.1)
    with warnings.catch_warnings(record=True):
        warnings.simplefilter("always")
        save_map(m, tmp_path / "t", occupied_thresh=0.6, free_thresh=0.1)
    np.testing.assert_array_equal(np.asarray(Image.open(tmp_path / "t.pgm")), [[254, 205, 205, 0, 0, 205]])
    meta = yaml.safe_load((tmp_path / "t.yaml").read_text())
    assert (meta["occupied_thresh"], meta["free_thresh"]) == (0.6, 0.1)


def test_save_scale_mode(tmp_path: Path) -> None:
    data = np.array([[0, 25, 50, 100, -1]], dtype=np.int8)
    m = OccupancyMap(data, 0.1, occupied_thresh=1.0, free_thresh=0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        yaml_path = save_map(m, tmp_path / "s", mode="scale")
    assert yaml_path == tmp_path / "s.yaml"
    rgba = np.asarray(Image.open(tmp_path / "s.png"))
    # grey (100 - v)/100 as GraphicsMagick writes it; unknown transparent mid grey
    np.testing.assert_array_equal(rgba[0, :, 0], [255, 191, 127, 0, 127])
    np.testing.assert_array_equal(rgba[0, :, 3], [255, 255, 255, 255, 0])
    back = load_map(yaml_path)
    assert back.mode == "scale"
    assert_same_map(back, m)


def test_save_raw_mode(tmp_path: Path) -> None:
    m = OccupancyMap(np.array([[0, 7, 100, -1]], dtype=np.int8), 0.1)
    yaml_path = save_map(m, tmp_path / "r", mode="raw")
    np.testing.assert_array_equal(np.asarray(Image.open(tmp_path / "r.pgm")), [[0, 7, 100, 255]])
    assert_same_map(load_map(yaml_path), m)


def test_save_warns_when_the_map_will_not_load_back_the_same(tmp_path: Path) -> None:
    m = OccupancyMap(np.array([[0, 100, -1]], dtype=np.int8), 0.1, free_thresh=0.25)
    with pytest.warns(UserWarning, match="will load back with 1 cells changed"):
        save_map(m, tmp_path / "w")  # unknown grey 205 has occ 0.196 < 0.25: it reads back as free
    scale = OccupancyMap(np.array([[0, 50, 100]], dtype=np.int8), 0.1)  # thresholds 0.65 / 0.196
    with pytest.warns(UserWarning, match="use mode='raw' for an exact copy"):
        save_map(scale, tmp_path / "w2", mode="scale")


@settings(max_examples=25, deadline=None)
@given(
    data=arrays(np.int8, st.tuples(st.integers(1, 6), st.integers(1, 6)), elements=st.sampled_from([-1, 0, 100])),
    mode=st.sampled_from(["trinary", "raw", "scale"]),
)
def test_round_trip_property(tmp_path_factory: pytest.TempPathFactory, data: np.ndarray, mode: str) -> None:
    tmp = tmp_path_factory.mktemp("rt")
    m = OccupancyMap(data, 0.05, (1.25, -2.5, 0.0))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        back = load_map(save_map(m, tmp / "m", mode=mode))
    assert_same_map(back, m)


@settings(max_examples=25, deadline=None)
@given(data=arrays(np.int8, st.tuples(st.integers(1, 5), st.integers(1, 5)), elements=st.integers(-1, 100)))
def test_round_trip_all_values(tmp_path_factory: pytest.TempPathFactory, data: np.ndarray) -> None:
    tmp = tmp_path_factory.mktemp("rt")
    for mode, (occ, free) in {"raw": (0.65, 0.196), "scale": (1.0, 0.0)}.items():
        m = OccupancyMap(data, 0.1, occupied_thresh=occ, free_thresh=free)
        assert_same_map(load_map(save_map(m, tmp / mode, mode=mode)), m)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"mode": "fancy"}, "unknown mode 'fancy'; accepted: trinary, scale, raw"),
        ({"image_format": "jpg"}, "image format 'jpg' is not one of pgm, png, bmp"),
        (
            {"mode": "scale", "image_format": "pgm"},
            "scale mode needs transparency for unknown cells, use png",
        ),
        ({"occupied_thresh": 1.2}, "0 <= free_thresh < occupied_thresh <= 1"),
        ({"free_thresh": 0.7}, "free_thresh < occupied_thresh"),
    ],
)
def test_save_bad_arguments(tmp_path: Path, kwargs: dict, message: str) -> None:
    m = OccupancyMap(np.zeros((2, 2), dtype=np.int8), 0.1)
    with pytest.raises(MapError, match=message):
        save_map(m, tmp_path / "x", **kwargs)


def test_save_errors_on_yaw_and_unwritable_folder(tmp_path: Path) -> None:
    m = OccupancyMap(np.zeros((2, 2), dtype=np.int8), 0.1, (0.0, 0.0, 0.3))
    with pytest.raises(MapError, match="origin yaw 0.3 is not supported"):
        save_map(m, tmp_path / "x")
    m = OccupancyMap(np.zeros((2, 2), dtype=np.int8), 0.1)
    with pytest.raises(MapError, match=r"cannot write .*nodir/x\.pgm: No such file"):
        save_map(m, tmp_path / "nodir" / "x")


@pytest.mark.parametrize("maxval", [255, 65535])
@pytest.mark.parametrize("mode", ["trinary", "scale", "raw"])
@pytest.mark.parametrize("negate", [False, True])
def test_grey_images_through_the_shade_table_give_the_per_pixel_rule(maxval, mode, negate):
    """The table path of grey images (a broadcast channel, no alpha) gives the grid of the per-pixel rule."""
    from spcotmhp.metric.map_io import pixels_to_grid

    # more pixels than shades: the table path
    grey = np.random.default_rng(maxval).integers(0, maxval + 1, (300, 300)).astype(np.int32)
    view = np.broadcast_to(grey[:, :, None], grey.shape + (3,))
    fast = pixels_to_grid(view, None, maxval, mode, negate, 0.65, 0.196)
    rule = pixels_to_grid(np.ascontiguousarray(view), None, maxval, mode, negate, 0.65, 0.196)
    assert fast.dtype == rule.dtype == np.int8 and fast.flags.c_contiguous
    np.testing.assert_array_equal(fast, rule)
