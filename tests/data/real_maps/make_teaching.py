"""Write a real map's teaching.csv, truth.csv and places.csv from its hand-picked teach_points.txt.

    python tests/data/real_maps/make_teaching.py tests/data/real_maps/nav2-depot

teach_points.txt: ``[english name]`` or ``[english name|日本語 の 名前]`` (phrase-segmented, as a dataset's words_ja)
opens a room; each following ``x,y`` line (metres, map frame) is one teaching event there; ``#`` lines are comments.
The n-th point of a room is said with the n-th sentence frame below (cycling), as people vary what they say.
"""

from __future__ import annotations

import csv
import sys
from pathlib import Path

EN = ("this is the {}", "{}", "here is the {}", "we are in the {}", "this place is called the {}", "the {}")
JA = ("ここ は {} です", "{}", "ここ が {}", "{} に 着きました", "ここ は {}", "{} です")


def read_points(path: Path) -> dict[tuple[str, str], list[tuple[float, float]]]:
    """{(english name, japanese name or ""): [(x, y), ...]} in file order."""
    rooms: dict[tuple[str, str], list[tuple[float, float]]] = {}
    room: tuple[str, str] | None = None
    for number, raw in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        if line.startswith("["):
            en, _, ja = line.strip("[]").partition("|")
            room = (en.strip(), ja.strip())
            rooms[room] = []
        elif room is None:
            raise SystemExit(f"{path} line {number}: a point before any [room]")
        else:
            x, y = (float(v) for v in line.split(","))
            rooms[room].append((x, y))
    return rooms


def write(folder: Path) -> None:
    """The three CSV files of ``folder`` from its teach_points.txt."""
    rooms = read_points(folder / "teach_points.txt")
    has_ja = any(ja for _, ja in rooms)
    with (
        open(folder / "teaching.csv", "w", newline="", encoding="utf-8") as teaching,
        open(folder / "truth.csv", "w", newline="", encoding="utf-8") as truth,
        open(folder / "places.csv", "w", newline="", encoding="utf-8") as places,
    ):
        rows, truths, names = (csv.writer(f, lineterminator="\n") for f in (teaching, truth, places))
        rows.writerow(["event", "x", "y", *(["words_ja"] if has_ja else []), "words_en"])
        truths.writerow(["event", "place"])
        names.writerow(["place", "name_ja", "name_en"])
        event = 0
        for k, ((en, ja), points) in enumerate(rooms.items()):
            names.writerow([k, ja.replace(" ", "") or en, en])
            for i, (x, y) in enumerate(points):
                said_ja = [JA[i % len(JA)].format(ja)] if has_ja else []
                rows.writerow([event, x, y, *said_ja, EN[i % len(EN)].format(en)])
                truths.writerow([event, k])
                event += 1


if __name__ == "__main__":
    for name in sys.argv[1:]:
        write(Path(name))
