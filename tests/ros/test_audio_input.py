"""Speech formats on the robot's topics (spcotmhp.ros.audio_input), without ROS: PCM chunks gathered into
utterances (by hand and as properties: any chunking of the same bytes gives the same samples; odd, over-long,
short and silent audio refused with AudioError, the rest of a refused utterance dropped), and the N-best JSON of
spcotmhp/hypotheses (every boundary; any JSON value or text gives pairs or a typed error, never another
exception; the pairs are POST /plan's, so the weights are the HTTP N-best's)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from spcotmhp.errors import EmptyInstruction, InstructionTooLarge, MalformedInstruction
from spcotmhp.planning.nbest import nbest_weights
from spcotmhp.planning.query import MAX_HYPOTHESES
from spcotmhp.ros.audio_input import MAX_HYPOTHESES_JSON, RATES, Utterance, check_rate, parse_hypotheses
from spcotmhp.speech.audio import MAX_SECONDS, NOISE_FLOOR, AudioError, to_16k_mono


def tone(n: int, rate: int = 16_000) -> np.ndarray:
    return (8000 * np.sin(2 * np.pi * 440 * np.arange(n) / rate)).astype("<i2")


def test_chunks_then_an_empty_message_make_one_utterance():
    u = Utterance()
    x = tone(3200)  # 0.2 s
    pcm = x.tobytes()
    assert u.add(pcm[:1000]) is None and u.add(pcm[1000:4000]) is None and u.add(pcm[4000:]) is None
    assert u.open
    out = u.add(b"")
    assert out is not None and out.dtype == np.int16 and len(out) == 3200
    assert abs((out.astype(float) - x).std() - NOISE_FLOOR) < 1.0  # the samples, with the noise floor only
    assert not u.open and u.add(b"") is None  # a second end: nothing


def test_little_endian_by_hand():
    u = Utterance()
    u.add(bytes([0x01, 0x02] * 1600))  # 0x0201 = 513 little-endian (258 if it were read big-endian)
    out = u.end()
    assert out is not None and abs(float(np.median(out)) - 513) < 3 * NOISE_FLOOR


def test_an_odd_message_drops_the_utterance_to_its_end():
    u = Utterance()
    u.add(tone(1600).tobytes())
    with pytest.raises(AudioError, match="3 bytes is not whole 16-bit samples"):
        u.add(b"abc")
    assert u.add(tone(1600).tobytes()) is None and u.add(b"") is None  # the rest dropped, with no other error
    u.add(tone(3200).tobytes())  # the next utterance is heard
    out = u.add(b"")
    assert out is not None and len(out) == 3200


@pytest.mark.parametrize("rate", [8000, 48000])
def test_an_utterance_longer_than_the_limit_is_refused_at_the_message_past_it(rate):
    u = Utterance(rate)
    limit = int(MAX_SECONDS * rate) * 2
    assert u.max_bytes == limit
    second = tone(rate, rate).tobytes()
    for _ in range(int(MAX_SECONDS)):
        assert u.add(second) is None
    assert u.size == limit  # exactly the limit is kept
    with pytest.raises(AudioError, match=f"longer than {MAX_SECONDS:.0f} s"):
        u.add(b"\x00\x00")
    assert u.size == 0 and u.chunks == []  # memory given back at once
    assert u.add(second) is None and u.end() is None  # dropped to its end


def test_short_and_silent_utterances_are_refused_at_their_end():
    u = Utterance()
    u.add(tone(800).tobytes())  # 50 ms
    with pytest.raises(AudioError, match="ms long"):
        u.add(b"")
    u.add(bytes(6400))
    with pytest.raises(AudioError, match="silent"):
        u.end()


def test_other_rates_are_resampled_to_16k():
    for rate in (8000, 44100):
        u = Utterance(rate)
        u.add(tone(rate // 2, rate).tobytes())
        out = u.end()
        assert out is not None and len(out) == 8000


@pytest.mark.parametrize("rate", [0, -16000, 16001, 96000, 44099])
def test_rates_not_listed_are_refused(rate):
    with pytest.raises(AudioError, match="one of 8000"):
        check_rate(rate)
    with pytest.raises(AudioError):
        Utterance(rate)
    assert 16_000 in RATES


@settings(max_examples=60, deadline=None)
@given(st.integers(1600, 8000), st.lists(st.integers(1, 4000), max_size=12))
def test_any_chunking_gives_the_same_samples(n, cuts):
    """Property: the samples depend on the bytes, not on how they were cut into messages (at even offsets)."""
    pcm = tone(n).tobytes()
    offsets = sorted({2 * (c % n) for c in cuts} | {0, len(pcm)})
    u = Utterance()
    for a, b in zip(offsets, offsets[1:], strict=False):
        u.add(pcm[a:b])
    out = u.add(b"")
    assert out is not None
    assert np.array_equal(out, to_16k_mono(tone(n), 16_000, "x"))


@settings(max_examples=100, deadline=None)
@given(st.lists(st.binary(max_size=64), max_size=10))
def test_any_messages_give_samples_none_or_an_audio_error(messages):
    """Property: hostile chunks (any lengths, any bytes) give samples, nothing, or AudioError; never more held
    than the limit."""
    u = Utterance()
    for m in [*messages, b""]:
        try:
            out = u.add(m)
        except AudioError:
            continue
        assert out is None or (out.dtype == np.int16 and out.ndim == 1)
        assert u.size <= u.max_bytes


# ---- hypotheses ---------------------------------------------------------------------------------------------------
def test_hypotheses_by_hand():
    text = json.dumps([{"text": "go to the kitchen", "score": 3}, {"text": "go to the kitten", "confidence": 1}])
    pairs = parse_hypotheses(text)
    assert pairs == [("go to the kitchen", 3), ("go to the kitten", 1)]
    assert nbest_weights(pairs, MAX_HYPOTHESES)[1] == pytest.approx([0.75, 0.25])


def test_the_pairs_are_post_plans():
    """The same list sent to POST /plan as ``nbest`` gives the same pairs, so the planner weighs them alike."""
    schemas = pytest.importorskip("spcotmhp.server.schemas")
    nbest = [{"text": "go to the bath", "score": -1.5}, {"text": "go to the path", "score": -2.0}]
    http = schemas.PlanRequest.model_validate({"nbest": nbest, "start": [0, 0]}).source()
    assert parse_hypotheses(json.dumps(nbest)) == http


@pytest.mark.parametrize(
    ("text", "error", "match"),
    [
        ("", MalformedInstruction, "not valid JSON"),
        ("go to the kitchen", MalformedInstruction, "not valid JSON"),
        ('{"text": "go", "score": 1}', MalformedInstruction, "must be a JSON list"),
        ('"go to the kitchen"', MalformedInstruction, "must be a JSON list"),
        ('[{"text": "go"}]', MalformedInstruction, "entry 0"),
        ('[{"text": "go", "score": 1, "confidence": 1}]', MalformedInstruction, "entry 0"),
        ('[{"text": "go", "score": 1, "lang": "en"}]', MalformedInstruction, "entry 0"),
        ('[{"text": "a", "score": 1}, ["b", 1]]', MalformedInstruction, "entry 1"),
        ("[" * 70_000 + "]" * 70_000, MalformedInstruction, "not valid JSON"),
        (json.dumps([{"text": "go", "score": 1}] * (MAX_HYPOTHESES + 1)), InstructionTooLarge, "51 hypotheses"),
        (" " * (MAX_HYPOTHESES_JSON + 1), InstructionTooLarge, "characters"),
    ],
)
def test_hostile_hypotheses_are_refused_with_one_line(text, error, match):
    with pytest.raises(error, match=match):
        parse_hypotheses(text)


@pytest.mark.parametrize("score", ['"0.9"', "true", "null", "1e999", "NaN"])
def test_bad_scores_and_texts_are_refused_as_every_n_best_is(score):
    with pytest.raises(MalformedInstruction, match="score"):
        parse_hypotheses(f'[{{"text": "go to the kitchen", "score": {score}}}]')
    with pytest.raises(MalformedInstruction, match="entry 0 must be"):
        parse_hypotheses('[{"text": 3, "score": 1}]')
    with pytest.raises(EmptyInstruction):
        parse_hypotheses("[]")


JSON = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=20),
    lambda kids: (
        st.lists(kids, max_size=5)
        | st.dictionaries(st.sampled_from(["text", "score", "confidence", "x"]), kids, max_size=3)
    ),
    max_leaves=20,
)


@settings(max_examples=300, deadline=None)
@given(st.one_of(JSON.map(json.dumps), st.text(max_size=200)))
def test_any_text_gives_pairs_or_a_typed_error(text):
    """Property: any JSON value or text gives valid [(text, score)] pairs (weights summing to 1) or one of
    MalformedInstruction, InstructionTooLarge, EmptyInstruction: never another exception."""
    try:
        pairs = parse_hypotheses(text)
    except (MalformedInstruction, InstructionTooLarge, EmptyInstruction):
        return
    texts, weights = nbest_weights(pairs, MAX_HYPOTHESES)
    assert np.isclose(weights.sum(), 1.0) and all(isinstance(t, str) for t in texts)
