"""CLI command ``spcotmhp examples``: the small inputs the README's Tour uses, written to one folder."""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Annotated

import typer

from spcotmhp.errors import SpcotmhpError
from spcotmhp.safe_write import atomic_write, check_output

FILES = ("map.yaml", "map.pgm", "robot.bag", "say.wav", "drawn-map.png", "tell.py")


def draw_flat(path: Path) -> None:
    """The README's drawn floor plan ("From a map you drew"), as a paint program saves it: a 10 m x 6 m flat in an
    RGB PNG of 200 x 120 pixels (0.05 m each), black walls 3 pixels wide on white, a kitchen (left) and a bedroom
    (right) above a hallway, each with a 1 m door; the image's bottom left corner is the origin."""
    from PIL import Image, ImageDraw

    image = Image.new("RGB", (200, 120), (255, 255, 255))
    pen = ImageDraw.Draw(image)
    pen.rectangle([0, 0, 199, 119], outline=(0, 0, 0), width=3)
    pen.line([(100, 0), (100, 70)], fill=(0, 0, 0), width=3)
    pen.line([(0, 70), (80, 70)], fill=(0, 0, 0), width=3)
    pen.line([(120, 70), (199, 70)], fill=(0, 0, 0), width=3)
    image.save(path, format="PNG")


def examples(
    out: Annotated[Path, typer.Option("--out", help="Folder to write the example inputs to.")] = Path("examples"),
    overwrite: Annotated[bool, typer.Option("--overwrite", help="Replace example files already in --out.")] = False,
) -> None:
    """Write the Tour's example inputs: map.yaml + map.pgm (a generated flat, seed 1), robot.bag (a ROS 1 bag of
    a teaching walk through that map: /amcl_pose and /speech; needs the extra 'ros'), say.wav (the spoken
    instruction "go to the bedroom via the corridor", 16 kHz mono), drawn-map.png (the floor plan the README's
    "From a map you drew" uses, :func:`draw_flat`) and tell.py (a ROS 2 client: a pose as AMCL sends it, an
    instruction, the node's answer; needs the extra 'ros2')."""
    from spcotmhp.datasets.bag_export import write_teaching_bag
    from spcotmhp.datasets.bundled import data_root
    from spcotmhp.datasets.synthetic import generate_environment
    from spcotmhp.metric.map_io import save_map

    for name in FILES:
        check_output(out / name, overwrite, (), SpcotmhpError, "--out") if out.is_dir() else None
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise SpcotmhpError(f"cannot create {out}: {exc.strerror or exc}") from None
    home = generate_environment("flat", seed=1)  # 45 utterances: a model learned from it names its places
    save_map(home.map, out / "map")
    atomic_write(out / "say.wav", lambda tmp: shutil.copyfile(data_root() / "examples" / "say.wav", tmp))
    atomic_write(out / "drawn-map.png", draw_flat)
    atomic_write(out / "tell.py", lambda tmp: shutil.copyfile(data_root() / "examples" / "tell.py", tmp))
    wrote = [
        (
            f"{out / 'map.yaml'} (+ map.pgm: {home.map.height} x {home.map.width} cells, places "
            f"{', '.join(home.place_names or [])})"
        ),
        f"{out / 'say.wav'}",
        f"{out / 'drawn-map.png'} (a drawn 10 m x 6 m flat: kitchen, bedroom, hallway; 0.05 m per pixel)",
        f"{out / 'tell.py'} (a ROS 2 client: a pose as AMCL sends it, then an instruction; extra 'ros2')",
    ]
    try:
        atomic_write(out / "robot.bag", lambda tmp: write_teaching_bag(home, tmp, every=3))
        wrote.append(f"{out / 'robot.bag'} ({len(home.tokens)} utterances on /speech, poses on /amcl_pose)")
    except SpcotmhpError as exc:
        typer.echo(f"warning: robot.bag not written: {exc}", err=True)
    typer.echo("wrote " + "\n      ".join(wrote))


def register(app: typer.Typer) -> None:
    """Add ``examples`` to ``app``."""
    app.command()(examples)
