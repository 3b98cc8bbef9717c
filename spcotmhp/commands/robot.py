"""CLI commands for robot logs: import a ROS bag as a dataset folder."""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Annotated

import typer


def import_bag(
    bag: Annotated[Path, typer.Argument(help="ROS 1 .bag file, or ROS 2 bag folder (metadata.yaml + .db3/.mcap).")],
    out: Annotated[Path, typer.Option("--out", help="Dataset folder to write.")],
    pose_topic: Annotated[str, typer.Option(help="Pose topic: PoseWithCovarianceStamped, PoseStamped or "
                                                 "Odometry.")] = "/amcl_pose",
    utterance_topic: Annotated[str, typer.Option(help="Utterance topic (std_msgs/String).")] = "/speech",
    map_yaml: Annotated[Path | None, typer.Option("--map", help="map_server YAML to copy into the dataset "
                                                     "(default: the last OccupancyGrid on --map-topic).")] = None,
    map_topic: Annotated[str, typer.Option(help="OccupancyGrid topic read when --map is not given.")] = "/map",
    step: Annotated[float, typer.Option(help="Trajectory spacing in metres along the path; 0 keeps every pose "
                                             "message.")] = 0.1,
    lang: Annotated[str, typer.Option(help="Language of the utterances: en (words_en) or ja (words_ja).")] = "en",
    overwrite: Annotated[bool, typer.Option(help="Replace a dataset already in --out.")] = False,
) -> None:
    """Import a robot's log as a dataset folder: trajectory.csv, teaching.csv (each utterance at the pose
    interpolated at its time) and the map."""
    from spcotmhp.datasets.bag_import import BagImportWarning
    from spcotmhp.datasets.bag_import import import_bag as run_import

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", BagImportWarning)
        summary = run_import(bag, out, pose_topic=pose_topic, utterance_topic=utterance_topic, map_yaml=map_yaml,
                             map_topic=map_topic, step=step, lang=lang, overwrite=overwrite, progress=True)
    for w in caught:
        typer.echo(f"warning: {w.message}", err=True)
    typer.echo(
        f"wrote {summary.folder}: {summary.n_events} teaching events, {summary.n_trajectory} trajectory poses "
        f"(from {summary.n_pose_messages} pose messages over {summary.duration_s:.1f} s, "
        f"{summary.path_length_m:.1f} m walked), map from {summary.map_source}")


def register(app: typer.Typer) -> None:
    """Add the robot-log commands to ``app``."""
    app.command("import-bag")(import_bag)
