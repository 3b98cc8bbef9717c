"""CLI commands for robots: import a ROS bag as a dataset folder, run the ROS 2 node, export for Nav2."""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Annotated

import typer

from spcotmhp.commands import body_options as bo


def import_bag(
    bag: Annotated[Path, typer.Argument(help="ROS 1 .bag file, or ROS 2 bag folder (metadata.yaml + .db3/.mcap).")],
    out: Annotated[Path, typer.Option("--out", help="Dataset folder to write.")],
    pose_topic: Annotated[
        str, typer.Option(help="Pose topic: PoseWithCovarianceStamped, PoseStamped or Odometry.")
    ] = "/amcl_pose",
    utterance_topic: Annotated[str, typer.Option(help="Utterance topic (std_msgs/String).")] = "/speech",
    map_yaml: Annotated[
        Path | None,
        typer.Option(
            "--map",
            help="map_server YAML to copy into the dataset (default: the last OccupancyGrid on --map-topic).",
        ),
    ] = None,
    map_topic: Annotated[str, typer.Option(help="OccupancyGrid topic read when --map is not given.")] = "/map",
    step: Annotated[
        float, typer.Option(help="Trajectory spacing in metres along the path; 0 keeps every pose message.")
    ] = 0.1,
    lang: Annotated[str, typer.Option(help="Language of the utterances: en (words_en) or ja (words_ja).")] = "en",
    overwrite: Annotated[bool, typer.Option("--overwrite", help="Replace a dataset already in --out.")] = False,
) -> None:
    """Import a robot's log as a dataset folder: trajectory.csv, teaching.csv (each utterance at the pose
    interpolated at its time) and the map."""
    from spcotmhp.datasets.bag_import import BagImportWarning
    from spcotmhp.datasets.bag_import import import_bag as run_import

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", BagImportWarning)
        summary = run_import(
            bag,
            out,
            pose_topic=pose_topic,
            utterance_topic=utterance_topic,
            map_yaml=map_yaml,
            map_topic=map_topic,
            step=step,
            lang=lang,
            overwrite=overwrite,
            progress=True,
        )
    for w in caught:
        typer.echo(f"warning: {w.message}", err=True)
    typer.echo(
        f"wrote {summary.folder}: {summary.n_events} teaching events, {summary.n_trajectory} trajectory poses "
        f"(from {summary.n_pose_messages} pose messages over {summary.duration_s:.1f} s, "
        f"{summary.path_length_m:.1f} m walked), map from {summary.map_source}"
    )


# long: a CLI command: its typer options and help (the drive mode's among them), then a short body
def ros2(
    model_dir: Annotated[Path, typer.Argument(help="Model folder (as written by `spcotmhp learn`).")],
    frame: Annotated[str, typer.Option(help="Frame of the model's map, of the plans and of the start poses.")] = "map",
    start_topic: Annotated[
        str, typer.Option(help="Pose topic (geometry_msgs/PoseWithCovarianceStamped) planned from.")
    ] = "/amcl_pose",
    record: Annotated[
        Path | None,
        typer.Option(
            help="Dataset folder that utterances on /spcotmhp/teach are "
            "appended to (created with the model's map if new)."
        ),
    ] = None,
    floor: Annotated[
        str | None,
        typer.Option(
            "--floor",
            metavar="F",
            help="A building's model: the floor the robot starts on (index or name); /spcotmhp/floor switches it.",
        ),
    ] = None,
    nav2_params: bo.Nav2Params = None,
    robot_radius: bo.RobotRadius = None,
    footprint: bo.Footprint = None,
    inflation_radius: bo.InflationRadius = None,
    cost_scaling_factor: bo.CostScaling = None,
    drive: Annotated[
        str | None,
        typer.Option(
            "--drive",
            metavar="HOW",
            help="Drive the plans with Nav2: follow_path (its controller follows the plan) or through_poses "
            "(NavigateThroughPoses through the waypoints and goal); needs nav2_msgs (make nav2-msgs).",
        ),
    ] = None,
    tf_timeout: Annotated[
        float,
        typer.Option(
            min=0.0, max=60.0, help="Seconds a pose in another frame waits for its transform to --frame (0: none)."
        ),
    ] = 1.0,
    audio_rate: Annotated[
        int,
        typer.Option(
            help="Sample rate (Hz) of the PCM on /spcotmhp/audio (signed 16-bit little-endian mono): 8000, 11025, "
            "16000, 22050, 24000, 32000, 44100 or 48000 (resampled to 16 kHz)."
        ),
    ] = 16000,
    audio_gap: Annotated[
        float,
        typer.Option(min=0.05, max=60.0, help="Seconds with no audio message that end an utterance (/spcotmhp/audio)."),
    ] = 1.0,
) -> None:
    """Run the ROS 2 node `spcotmhp` (extra ros2): instructions on /spcotmhp/instruction become nav_msgs/Path
    plans on /spcotmhp/plan from the robot's pose; status JSON on /spcotmhp/status, places for RViz on
    /spcotmhp/places. A building's model: the current floor's segment of the route on /spcotmhp/plan, the floor
    switched by /spcotmhp/floor."""
    from spcotmhp.building.io import is_building_model
    from spcotmhp.ros import require_rclpy

    require_rclpy()
    body = bo.body_from_options(nav2_params, robot_radius, footprint, inflation_radius, cost_scaling_factor)
    if is_building_model(model_dir):
        from spcotmhp.errors import SpcotmhpError
        from spcotmhp.ros.building_node import run_building_node

        if record is not None:
            raise SpcotmhpError("--record is for a single floor's model; a building's node teaches without recording")
        if drive is not None:
            raise SpcotmhpError("--drive is for a single floor's model; a building's node publishes plans only")
        run_building_node(
            model_dir, floor, frame, start_topic, progress=lambda line: typer.echo(line, err=True), body=body
        )
        return
    if drive is not None:
        from spcotmhp.ros.drive import MODES

        if drive not in MODES:
            raise typer.BadParameter(f"--drive must be one of {', '.join(MODES)}, got {drive!r}")
    if floor is not None:
        raise typer.BadParameter(
            f"--floor is for a building's model (learned from a building folder); {model_dir} is not one"
        )
    from spcotmhp.errors import SpcotmhpError
    from spcotmhp.ros.hearing import HearingSettings
    from spcotmhp.ros.node import run_node

    try:
        hearing = HearingSettings(audio_rate=audio_rate, audio_gap_s=audio_gap)
    except SpcotmhpError as exc:
        raise typer.BadParameter(str(exc)) from None
    run_node(
        model_dir,
        frame=frame,
        start_topic=start_topic,
        record=record,
        progress=lambda line: typer.echo(line, err=True),
        body=body,
        drive=drive,
        tf_timeout_s=tf_timeout,
        hearing=hearing,
    )


def export_nav2(
    model_dir: Annotated[Path, typer.Argument(help="Model folder (as written by `spcotmhp learn`).")],
    out: Annotated[
        Path,
        typer.Option(
            "--out",
            help="Folder to write (route_graph.geojson, README.md, and keepout.yaml + keepout.pgm with --avoid).",
        ),
    ],
    avoid: Annotated[
        list[str] | None,
        typer.Option(help="A place to keep out of (its name, e.g. kitchen or 'east corridor'); repeat for more."),
    ] = None,
    frame: Annotated[str, typer.Option(help="Frame of the route graph's nodes.")] = "map",
    overwrite: Annotated[bool, typer.Option("--overwrite", help="Replace an existing --out folder.")] = False,
) -> None:
    """Export the learned map for Nav2: a Route Server graph (places as nodes, partial paths as edges) and,
    with --avoid, a keepout mask for the costmap filters. A building's model: one graph per floor (floorF/) with
    its stair and lift stops as nodes, and connectors.json."""
    from spcotmhp.building.io import is_building_model
    from spcotmhp.ros.nav2_export import export_nav2 as run_export

    if is_building_model(model_dir):
        from spcotmhp.ros.nav2_building import export_building

        run_export = export_building
    summary = run_export(model_dir, out, avoid=avoid or [], frame=frame, overwrite=overwrite)
    typer.echo(summary)


def register(app: typer.Typer) -> None:
    """Add the robot commands to ``app``."""
    app.command("import-bag")(import_bag)
    app.command("ros2")(ros2)
    app.command("export-nav2")(export_nav2)
