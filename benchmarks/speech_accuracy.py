"""Speech recognition accuracy on instructions synthesised by espeak-ng (several voices and speaking rates).

An instruction counts as right when the planner's N-best parser (Eq. 25 bags) gives the right goal, the right
waypoints in order and the right places to avoid (the top word of each bag). Prints a table per voice and rate
and the decoding time per second of audio.

    python benchmarks/speech_accuracy.py [--n 40] [--voices en-us,en-us+m3,en-us+f2,en] [--rates 140,175]
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import time
from collections import defaultdict

import numpy as np

from spcotmhp.planning.instructions import parse_nbest
from spcotmhp.speech import Recogniser, load_audio

PLACES_3LDK_06 = [
    "bath",
    "bedroom",
    "corridor",
    "dining",
    "entrance",
    "kitchen",
    "living",
    "toilet",
    "washroom",
]
GOAL = ["go to the", "take me to the", "bring me to the"]
VIA = ["via the", "through the", "passing by the"]
AVOID = ["avoiding the", "without passing through the"]


def instructions(n: int, seed: int = 0) -> list[tuple[str, tuple]]:
    """n seeded sentences with their expected (goal, waypoints, avoid): a quarter goal only, half with one
    waypoint, a quarter with a place to avoid."""
    rng = np.random.default_rng(seed)
    out = []
    for k in range(n):
        g, w = rng.choice(PLACES_3LDK_06, 2, replace=False)
        goal = f"{GOAL[rng.integers(len(GOAL))]} {g}"
        if k % 4 == 0:
            out.append((goal, (g, (), ())))
        elif k % 4 == 3:
            out.append((f"{goal} {AVOID[rng.integers(len(AVOID))]} {w}", (g, (), (w,))))
        else:
            out.append((f"{goal} {VIA[rng.integers(len(VIA))]} {w}", (g, (w,), ())))
    return out


def understood(hypotheses, places) -> tuple:
    """(goal, waypoints, avoid) as the top word of each bag of the N-best parse."""
    ins = parse_nbest(hypotheses, places, lang="en")

    def top(q):
        return max(q.words, key=q.words.get)

    return top(ins.goal), tuple(top(w) for w in ins.waypoints), tuple(top(a) for a in ins.avoid)


def synthesise(text: str, voice: str, rate: int) -> bytes:
    return subprocess.run(
        ["espeak-ng", "-v", voice, "-s", str(rate), "--stdout", text], capture_output=True, check=True
    ).stdout


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=40)
    ap.add_argument("--voices", default="en-us,en-us+m3,en-us+f2,en")
    ap.add_argument("--rates", default="140,175")
    ap.add_argument("--nbest", type=int, default=5)
    ap.add_argument("--no-spelling-variants", action="store_true")
    ap.add_argument("--verbose", action="store_true")
    args = ap.parse_args()
    if shutil.which("espeak-ng") is None:
        sys.exit("espeak-ng is not installed (apt-get install espeak-ng)")
    rec = Recogniser(PLACES_3LDK_06, spelling_variants=not args.no_spelling_variants)
    sentences = instructions(args.n)
    right, seconds, audio = defaultdict(int), defaultdict(float), defaultdict(float)
    for voice in args.voices.split(","):
        for rate in map(int, args.rates.split(",")):
            for text, expected in sentences:
                samples = load_audio(synthesise(text, voice, rate))
                t0 = time.perf_counter()
                hyps = rec.recognise(samples, args.nbest)
                seconds[voice, rate] += time.perf_counter() - t0
                audio[voice, rate] += len(samples) / 16000
                try:
                    got = understood(hyps, PLACES_3LDK_06)
                except Exception as exc:  # noqa: BLE001 - a failed parse counts as wrong
                    got = f"error: {exc}"
                right[voice, rate] += got == expected
                if args.verbose and got != expected:
                    print(f"  {voice} {rate}: {text!r} -> {hyps[0][0]!r} {got}")
    print(f"{'voice':<12} {'rate':>5} {'right':>9} {'accuracy':>9} {'decode s / audio s':>19}")
    for (voice, rate), ok in right.items():
        print(
            f"{voice:<12} {rate:>5} {ok:>4}/{len(sentences):<4} {ok / len(sentences):>9.1%} "
            f"{seconds[voice, rate] / audio[voice, rate]:>19.3f}"
        )
    total = sum(right.values())
    print(
        f"{'all':<12} {'':>5} {total:>4}/{len(sentences) * len(right):<4} {total / (len(sentences) * len(right)):>9.1%}"
    )


if __name__ == "__main__":
    main()
