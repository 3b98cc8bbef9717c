"""Speech on the robot: the node's ``spcotmhp/audio`` and ``spcotmhp/hypotheses`` topics (issue 36, item 4).

* ``spcotmhp/audio`` (std_msgs/UInt8MultiArray, in): PCM chunks of a spoken instruction, in the format and with
  the utterance boundaries of :mod:`spcotmhp.ros.audio_input` (signed 16-bit little-endian mono at the node's
  ``audio_rate``; an empty message, or ``audio_gap_s`` with no message, ends the utterance). The utterance is
  recognised with the recogniser the CLI and ``POST /plan/audio`` use: pocketsphinx constrained by the grammar
  of the planner's place words (``cached_recogniser(place_words)``, extra ``speech``), its N-best list weighted
  as theirs is (Eq. 25). Recognition runs on a thread of its own (a 3 s utterance takes about a second), so
  instructions, feedback and poses keep being served; at most MAX_PENDING utterances wait or run (past that,
  SpeechBusy). Its result comes back to the executor's thread through a guard condition.
* ``spcotmhp/hypotheses`` (std_msgs/String, in): an external recogniser's N-best list, JSON as
  :func:`~spcotmhp.ros.audio_input.parse_hypotheses` reads it, weighted as the HTTP N-best is.

Either way, a ``heard`` status (the hypotheses, best first, and where they came from) comes first, then the
hypotheses go to the node's ``act`` as an instruction on ``spcotmhp/instruction`` does (planned, and driven with
``--drive``; a best hypothesis that is a stop word stops the robot). Any failure (odd or over-long audio, garbage
JSON, nothing recognised, no speech extra) is an ``error`` status naming its cause, never the node's end.
"""

from __future__ import annotations

import collections
import functools
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import String, UInt8MultiArray

from spcotmhp.errors import SpcotmhpError, SpeechBusy
from spcotmhp.ros.audio_input import Utterance, check_rate, parse_hypotheses
from spcotmhp.ros.shapes import error_status
from spcotmhp.ros.worker import BoundedWorker

# reliable, and deep enough for a burst: with KEEP_LAST a reader that falls behind loses the oldest chunks (the
# middle of an utterance); 600 chunks are a minute at 0.1 s each, a few MB at most
AUDIO_QOS = QoSProfile(depth=600, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.VOLATILE)
MAX_PENDING = 2  # utterances being recognised or waiting: one said while the last is recognised is kept, no more
NBEST = 5  # hypotheses kept, as the CLI's and POST /plan/audio's default
AUDIO_GAP_S = 1.0  # no message for this long ends an utterance: audio drivers send a chunk every 10-100 ms

Hypotheses = list[tuple[str, float]]


@dataclass(frozen=True)
class HearingSettings:
    """The node's speech options: the audio's sample rate (Hz, one of audio_input.RATES), the gap (s) that ends an
    utterance with no empty message, and the hypotheses kept."""

    audio_rate: int = 16_000
    audio_gap_s: float = AUDIO_GAP_S
    nbest: int = NBEST

    def __post_init__(self) -> None:
        check_rate(self.audio_rate)
        if not 0.05 <= self.audio_gap_s <= 60.0:
            raise SpcotmhpError(f"the audio gap must be 0.05 to 60 s, not {self.audio_gap_s}")


class Hearing:
    """The two speech topics of an rclpy ``node`` (module docstring). ``place_words`` gives the planner's place
    words now (a teach can add some), ``act(hypotheses, label)`` serves a recognised instruction on the
    executor's thread, ``report`` publishes a status dict."""

    def __init__(
        self,
        node: Any,
        settings: HearingSettings,
        place_words: Callable[[], tuple[str, ...]],
        act: Callable[[Hypotheses, str], None],
        report: Callable[[dict], None],
        qos: Any,
    ) -> None:
        self.node, self.settings, self.place_words, self.act, self.report = node, settings, place_words, act, report
        self.utterance = Utterance(settings.audio_rate)
        self.worker = BoundedWorker("spcotmhp-speech", MAX_PENDING, lambda n: SpeechBusy(
            f"{n} utterances are being recognised or waiting (the limit); say it again shortly"))  # fmt: skip
        self.results: collections.deque[tuple[Hypotheses | None, BaseException | None]] = collections.deque()
        self.wake = node.create_guard_condition(self.on_results)  # the worker's results, on the executor's thread
        self.gap = node.create_timer(settings.audio_gap_s, self.on_gap)
        self.gap.cancel()
        node.create_subscription(UInt8MultiArray, "spcotmhp/audio", self.on_audio, AUDIO_QOS)
        node.create_subscription(String, "spcotmhp/hypotheses", self.on_hypotheses, qos)

    # ---- topics (executor's thread) ----------------------------------------------------------------------------
    def on_audio(self, msg: UInt8MultiArray) -> None:
        self._guarded(lambda: self._chunk(bytes(msg.data)), "audio")

    def _chunk(self, data: bytes) -> None:
        try:
            samples = self.utterance.add(data)
        finally:
            self.gap.reset() if self.utterance.open else self.gap.cancel()
        if samples is not None:
            self.recognise(samples)

    def on_gap(self) -> None:
        """No message for ``audio_gap_s``: the utterance under way ends there (module docstring)."""
        self.gap.cancel()
        self._guarded(lambda: self._ended(self.utterance.end()), "audio")

    def _ended(self, samples: np.ndarray | None) -> None:
        if samples is not None:
            self.recognise(samples)

    def on_hypotheses(self, msg: String) -> None:
        def serve() -> None:
            hypotheses = parse_hypotheses(msg.data)
            self._heard(hypotheses, "hypotheses")

        self._guarded(serve, "hypotheses")  # the JSON is not echoed: it may be long

    def on_results(self) -> None:
        while self.results:
            hypotheses, exc = self.results.popleft()
            if exc is not None:
                self.report(_error(exc, "audio"))
            elif hypotheses is not None:
                self._guarded(functools.partial(self._heard, hypotheses, "audio"), "audio")

    def _heard(self, hypotheses: Hypotheses, source: str) -> None:
        heard = [{"text": t, "score": s} for t, s in hypotheses]
        self.report({"kind": "heard", "ok": True, "source": source, "hypotheses": heard})
        self.act(hypotheses, f"spcotmhp/{source}")

    def _guarded(self, step: Callable[[], None], source: str) -> None:
        """Run ``step``; a failure is an error status (the node keeps serving), an unexpected one also logged."""
        try:
            step()
        except SpcotmhpError as exc:
            self.report(_error(exc, source))
        except Exception as exc:  # noqa: BLE001 - the node must keep serving; the cause is logged
            self.node.get_logger().error(f"{source}: internal error {type(exc).__name__}: {exc}")
            self.report(_error(RuntimeError(f"internal error ({type(exc).__name__}: {exc})"), source))

    # ---- recognition (the worker's thread) ---------------------------------------------------------------------
    def recognise(self, samples: np.ndarray) -> None:
        """Queue ``samples`` (16 kHz int16) for the recogniser; SpeechBusy when MAX_PENDING wait or run."""
        self.worker.submit(self._recognise, samples, self.place_words())

    def _recognise(self, samples: np.ndarray, words: tuple[str, ...]) -> None:
        try:
            from spcotmhp.speech import cached_recogniser

            result: tuple[Hypotheses | None, BaseException | None] = (
                cached_recogniser(words).recognise(samples, self.settings.nbest, "the utterance on spcotmhp/audio"),
                None,
            )
        except Exception as exc:  # noqa: BLE001 - answered on the status topic by the executor's thread
            result = (None, exc)
        self.results.append(result)
        self.wake.trigger()

    def warm_up(self) -> None:
        """Build the recogniser for the place words now, on the worker (when the speech extra is installed)."""
        import importlib.util

        if importlib.util.find_spec("pocketsphinx") is not None:
            from spcotmhp.speech import cached_recogniser

            self.worker.pool.submit(cached_recogniser, self.place_words())  # not counted: nothing waits for it

    def shutdown(self) -> None:
        self.worker.shutdown()


def _error(exc: BaseException, source: str) -> dict:
    if not isinstance(exc, SpcotmhpError):  # the recogniser's own failure (pocketsphinx): named, not hidden
        exc = RuntimeError(f"internal error ({type(exc).__name__}: {exc})")
    return {**error_status(exc), "source": source}
