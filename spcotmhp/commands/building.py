"""CLI pieces for buildings (spcotmhp/building/): ``synth building``, and the building branches of ``learn`` and
``plan``, which dispatch here when their folder holds a building.yaml (a building folder) or a building.json (a
building model)."""

from __future__ import annotations

from pathlib import Path

import typer

from spcotmhp.errors import BuildingError


def synth_building(
    kind: str,
    out: Path,
    floors: int | None,
    rooms: int | None,
    size: int | None,
    seed: int,
    word_noise: float,
    events_per_room: int,
    overwrite: bool,
) -> None:
    """``spcotmhp synth building --floors N``: a seeded building of houses (:mod:`spcotmhp.building.synthetic`)."""
    from spcotmhp.building.synthetic import check_building_target, generate_building, lift_only_floor, write_building

    if kind != "building":
        raise BuildingError(f"--floors makes a building: give KIND building, not {kind!r}")
    if size is not None:
        raise BuildingError("--size is not used for a building (every floor is a house of --rooms rooms)")
    check_building_target(out, overwrite)
    b = generate_building(floors or 2, seed=seed, n_rooms=rooms, events_per_room=events_per_room,
                          word_noise=word_noise)  # fmt: skip
    write_building(b, out, overwrite=overwrite)
    spec = b.spec
    lines = [f"wrote {out}: {len(spec.floors)} floors, {sum(d.n_events for d in b.floors.values())} events"]
    for f in spec.floors:
        d = b.floors[f.index]
        lines.append(f"  floor {f.index} ({f.name}, {f.dataset}): {len(d.place_names or [])} places, "
                     f"map {d.map.height} x {d.map.width}")  # fmt: skip
    for c in spec.connectors:
        lines.append(f"  {c.kind} '{c.name}': floors {', '.join(str(s.floor) for s in c.stops)}, {c.cost_m:g} m")
    only = lift_only_floor(spec)
    if only is not None:
        lines.append(f"  floor {only} is reached by the lift only")
    typer.echo("\n".join(lines))
