"""The frozen instruction corpora read by the current code (issue 34): for each corpus and language, how many
sentences are read as labelled (right), refused although the label reads them (or refused naming another word),
and read otherwise than labelled (silently wrong). A corpus measured once on arrival, before any change made
after reading it, gives the first-sight figure (docs/instructions.md); run again later it is a regression check.

    .venv/bin/python benchmarks/corpora.py [CORPUS_DIR ...] [--list refused,wrong]

CORPUS_DIR: a folder with an instructions.csv in the corpus format (tests/helpers/corpus.py), maybe with a
relabelled.csv (rows whose label a later issue's rule changed, read instead of the frozen row and counted in the
last column); default: every corpus under tests/data/.
"""

from __future__ import annotations

import argparse
import platform
import sys
import warnings
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # the corpus helpers live in tests/helpers


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("corpora", nargs="*", type=Path, help="folders with an instructions.csv")
    parser.add_argument("--list", default="", help="comma-separated verdicts to list row by row (refused,wrong)")
    args = parser.parse_args(argv)
    from tests.helpers.corpus import DATA, corpus_rows, verdict

    folders = args.corpora or sorted(p.parent for p in DATA.glob("*/instructions.csv"))
    listed = {v for v in args.list.split(",") if v}
    print(f"machine: {platform.machine()}, Python {platform.python_version()}")
    print("| corpus | language | sentences | right | refused | silently wrong | relabelled |")
    print("|---|---|---|---|---|---|---|")
    lines: list[str] = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for folder in folders:
            by_lang: dict[str, Counter] = {}
            for row in corpus_rows(folder):
                kind, what = verdict(row)
                lang = row["vocabulary"].rsplit("_", 1)[1]
                by_lang.setdefault(lang, Counter())[kind] += 1
                by_lang[lang]["relabelled"] += bool(row.get("relabelled"))
                if kind in listed:
                    lines.append(f"{folder.name} {kind}: {row['text']!r}: {what}")
            for lang, c in sorted(by_lang.items()):
                n = c["right"] + c["refused"] + c["wrong"]
                print(
                    f"| {folder.name} | {lang} | {n} | {c['right']} ({100 * c['right'] / n:.1f} %) | {c['refused']} | "
                    f"{c['wrong']} ({100 * c['wrong'] / n:.1f} %) | {c['relabelled']} |"
                )
    for line in lines:
        print(line)


if __name__ == "__main__":
    main()
