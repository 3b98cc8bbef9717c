"""Speech on the robot's topics, before recognition: PCM chunks gathered into utterances, N-best JSON read.

No rclpy here (the node's side is :mod:`spcotmhp.ros.hearing`), so the formats are tested without ROS.

**Audio** (``spcotmhp/audio``, std_msgs/UInt8MultiArray; its layout is ignored, ``data`` is the bytes): raw PCM,
signed 16-bit little-endian, mono, at ``rate`` Hz (a node option; one of RATES, resampled to the recogniser's
16 kHz by :func:`spcotmhp.speech.audio.to_16k_mono`, as a WAV file at that rate is). The bytes of consecutive
messages form one utterance; an **empty message ends it** (push-to-talk released), and so does a gap of the
node's ``audio_gap_s`` with no message (a publisher that stops sending without the empty message; the node's
timer calls :meth:`Utterance.end`). Every message must hold whole samples (an even number of bytes): an odd one
means the stream is not 16-bit PCM or lost a byte, so the utterance is refused (AudioError) and the rest of it,
up to its end, dropped without another error. So is an utterance past MAX_SECONDS (the recogniser's one limit,
60 s: 1.9 MB at 16 kHz), at the message that passes it: memory stays bounded whatever is sent.

**Hypotheses** (``spcotmhp/hypotheses``, std_msgs/String): an external recogniser's N-best list as JSON, a list
of ``{"text": "go to the kitchen", "score": 0.8}`` objects, as ``POST /plan``'s ``nbest`` (``confidence`` is
accepted in place of ``score``, the name several recognisers use). Scores are confidences >= 0 or
log-probabilities <= 0, weighed by the planner as the HTTP N-best is (:func:`spcotmhp.planning.nbest.nbest_weights`).
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from spcotmhp.errors import InstructionTooLarge, MalformedInstruction
from spcotmhp.language.wording import excerpt
from spcotmhp.planning.nbest import nbest_weights
from spcotmhp.planning.query import MAX_CHARS, MAX_HYPOTHESES
from spcotmhp.speech.audio import MAX_SECONDS, AudioError, to_16k_mono

SAMPLE_BYTES = 2  # signed 16-bit
# the rates audio drivers send (audio_capture, PortAudio, PulseAudio defaults); an arbitrary rate would make the
# polyphase resampler's ratio (16000 / gcd) and its filter as long as the rate itself
RATES = (8000, 11025, 16000, 22050, 24000, 32000, 44100, 48000)
SCORE_KEYS = ("score", "confidence")
# the longest N-best JSON read: MAX_HYPOTHESES hypotheses of MAX_CHARS characters, with room for the keys and
# escapes (six characters per \uXXXX); anything longer is refused before it is parsed
MAX_HYPOTHESES_JSON = MAX_HYPOTHESES * (6 * MAX_CHARS + 64)


def check_rate(rate: int) -> int:
    """``rate`` when it is one of RATES; else AudioError naming them."""
    if rate not in RATES:
        raise AudioError(f"the audio rate must be one of {', '.join(map(str, RATES))} Hz, not {rate}")
    return rate


@dataclass
class Utterance:
    """The chunks of the utterance being heard (module docstring): :meth:`add` each message's bytes; the samples
    (16 kHz mono int16, for the recogniser) come back when an empty message or :meth:`end` closes it."""

    rate: int = 16_000
    chunks: list[bytes] = field(default_factory=list)
    size: int = 0
    dropping: bool = False  # the utterance was refused: its rest is dropped up to its end

    def __post_init__(self) -> None:
        check_rate(self.rate)

    @property
    def max_bytes(self) -> int:
        return int(MAX_SECONDS * self.rate) * SAMPLE_BYTES

    @property
    def open(self) -> bool:
        """Whether an utterance is under way (chunks held, or being dropped): a gap then ends it."""
        return self.size > 0 or self.dropping

    def add(self, data: bytes) -> np.ndarray | None:
        """Take one message's bytes: the utterance's samples when ``data`` is empty (its end) and one was heard,
        else None. AudioError for an odd number of bytes or an utterance past MAX_SECONDS (then dropped)."""
        if not data:
            return self.end()
        if self.dropping:
            return None
        if len(data) % SAMPLE_BYTES:
            self._drop()
            raise AudioError(
                f"an audio message of {len(data)} bytes is not whole 16-bit samples (an even number of bytes: "
                "signed 16-bit little-endian mono PCM); the utterance is dropped"
            )
        if self.size + len(data) > self.max_bytes:
            seconds = (self.size + len(data)) / SAMPLE_BYTES / self.rate
            self._drop()
            raise AudioError(
                f"the utterance is longer than {MAX_SECONDS:.0f} s ({seconds:.1f} s heard at {self.rate} Hz with no "
                "end: an empty message ends one); it is dropped"
            )
        self.chunks.append(bytes(data))
        self.size += len(data)
        return None

    def end(self) -> np.ndarray | None:
        """Close the utterance: its samples at 16 kHz (AudioError when too short or silent), or None when nothing
        was held (an end with no utterance, or the end of a dropped one)."""
        chunks, dropped = self.chunks, self.dropping
        self._drop()
        self.dropping = False
        if dropped or not chunks:
            return None
        pcm = np.frombuffer(b"".join(chunks), dtype="<i2").astype(np.int16)
        return to_16k_mono(pcm, self.rate, "the utterance on spcotmhp/audio")

    def _drop(self) -> None:
        self.chunks, self.size, self.dropping = [], 0, True


def parse_hypotheses(text: str) -> list[tuple[str, float]]:
    """An N-best JSON text (module docstring) as [(text, score)] for the planner. MalformedInstruction for a
    text that is not such a list (naming the entry) or a score that is not a finite number, EmptyInstruction for
    an empty list, InstructionTooLarge for one past the limits."""
    if len(text) > MAX_HYPOTHESES_JSON:
        raise InstructionTooLarge(
            f"the N-best JSON has {len(text)} characters, more than the {MAX_HYPOTHESES_JSON} accepted"
        )
    try:
        value: Any = json.loads(text)
    except (json.JSONDecodeError, RecursionError) as exc:
        why = exc.msg if isinstance(exc, json.JSONDecodeError) else "nested too deeply"
        raise MalformedInstruction(
            f'the N-best list is not valid JSON ({why}); send [{{"text": "...", "score": 0.9}}, ...]'
        ) from None
    if not isinstance(value, list):
        raise MalformedInstruction(
            f'the N-best list must be a JSON list of {{"text", "score"}} objects, got {excerpt(value)}'
        )
    if len(value) > MAX_HYPOTHESES:
        raise InstructionTooLarge(
            f"the N-best list has {len(value)} hypotheses, more than the {MAX_HYPOTHESES} accepted"
        )
    out = []
    for i, entry in enumerate(value):
        keys = [k for k in SCORE_KEYS if isinstance(entry, dict) and k in entry]
        if not isinstance(entry, dict) or len(keys) != 1 or set(entry) != {"text", keys[0]}:
            raise MalformedInstruction(
                f'N-best entry {i} must be {{"text": ..., "score": ...}} ("confidence" for "score"), got '
                f"{excerpt(entry)}"
            )
        out.append((entry["text"], entry[keys[0]]))
    nbest_weights(out, MAX_HYPOTHESES)  # text and score types checked where every N-best list's are
    return out
