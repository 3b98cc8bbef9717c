"""Speech input: WAV conversion, pronunciations, the recognition grammar, N-best weights, and recognition of
instructions synthesised by espeak-ng (the recognition tests skip only when pocketsphinx or espeak-ng is missing)."""

from __future__ import annotations

import io
import shutil
import subprocess
import warnings

import numpy as np
import pytest
from scipy.io import wavfile

from spcotmhp.errors import InstructionError, SpcotmhpError
from spcotmhp.planning.instructions import parse_nbest
from spcotmhp.speech.audio import NOISE_FLOOR, RATE, AudioError, load_audio, read_wav, to_16k_mono
from spcotmhp.speech.jsgf import CONNECTORS, GOAL_MARKERS, MARKERS, instruction_grammar
from spcotmhp.speech.lexicon import PHONES, dictionary_pronunciations, letter_to_sound

PLACES = [
    "bath",
    "bedroom",
    "corridor",
    "dining",
    "entrance",
    "kitchen",
    "living",
    "toilet",
    "washroom",
]  # 3LDK_06
# (sentence, (goal, waypoints, places to avoid)) -- 12 instructions over 3LDK_06's English place words
INSTRUCTIONS = [
    ("go to the bedroom via the corridor", ("bedroom", ("corridor",), ())),
    ("go to the kitchen", ("kitchen", (), ())),
    ("take me to the toilet through the living", ("toilet", ("living",), ())),
    ("go to the bath via the washroom", ("bath", ("washroom",), ())),
    ("bring me to the dining", ("dining", (), ())),
    ("go to the entrance passing by the kitchen", ("entrance", ("kitchen",), ())),
    ("take me to the washroom through the corridor", ("washroom", ("corridor",), ())),
    ("go to the living avoiding the dining", ("living", (), ("dining",))),
    ("go to the bedroom via the kitchen and then the corridor", ("bedroom", ("kitchen", "corridor"), ())),
    ("take me to the toilet", ("toilet", (), ())),
    ("go to the dining through the living", ("dining", ("living",), ())),
    ("bring me to the entrance without passing through the corridor", ("entrance", (), ("corridor",))),
]


def _wav_bytes(samples: np.ndarray, rate: int) -> bytes:
    buf = io.BytesIO()
    wavfile.write(buf, rate, samples)
    return buf.getvalue()


def _tone(rate: int, seconds: float = 0.5, freq: float = 1000.0, amp: float = 10000.0) -> np.ndarray:
    t = np.arange(int(rate * seconds)) / rate
    return amp * np.sin(2 * np.pi * freq * t)


def _peak_hz(x: np.ndarray, rate: int = RATE) -> float:
    spectrum = np.abs(np.fft.rfft(x.astype(float) * np.hanning(len(x))))
    return float(np.fft.rfftfreq(len(x), 1 / rate)[np.argmax(spectrum)])


# ---- audio -----------------------------------------------------------------------------------------------
def test_16k_mono_16bit_passes_through_with_only_the_noise_floor():
    x = _tone(RATE).astype(np.int16)
    out = load_audio(_wav_bytes(x, RATE))
    assert out.dtype == np.int16 and out.shape == x.shape
    diff = out.astype(float) - x
    assert abs(diff.std() - NOISE_FLOOR) < 0.5 and abs(diff.mean()) < 0.5


@pytest.mark.parametrize("rate", [8000, 22050, 44100, 48000])
def test_other_rates_are_resampled_keeping_pitch_and_duration(rate):
    out = load_audio(_wav_bytes(_tone(rate).astype(np.int16), rate))
    assert len(out) == RATE // 2
    assert _peak_hz(out) == pytest.approx(1000.0, abs=3.0)
    assert np.abs(out).max() == pytest.approx(10000, rel=0.02)


def test_stereo_is_averaged_and_sample_formats_are_scaled():
    tone = _tone(RATE)
    stereo = np.stack([tone, np.zeros_like(tone)], axis=1).astype(np.int16)
    assert np.abs(load_audio(_wav_bytes(stereo, RATE))).max() == pytest.approx(5000, rel=0.01)
    as_float = (tone / 32767.0).astype(np.float32)
    as_u8 = np.round(tone / 256.0 + 128).astype(np.uint8)
    as_i32 = (tone * 65536.0).astype(np.int32)
    for samples in (as_float, as_u8, as_i32):
        out = load_audio(_wav_bytes(samples, RATE))
        assert np.abs(out).max() == pytest.approx(10000, rel=0.02), samples.dtype


def test_read_wav_reports_rate_and_channels(tmp_path):
    path = tmp_path / "a.wav"
    wavfile.write(path, 22050, np.zeros((2205, 2), dtype=np.int16))
    samples, rate, channels = read_wav(path)
    assert (samples.shape, rate, channels) == ((2205, 2), 22050, 2)


def test_audio_errors(tmp_path):
    with pytest.raises(AudioError, match=r"audio file .*nope\.wav does not exist"):
        load_audio(tmp_path / "nope.wav")
    (tmp_path / "empty.wav").write_bytes(b"")
    with pytest.raises(AudioError, match=r"empty\.wav is empty \(0 bytes\); expected a WAV file"):
        load_audio(tmp_path / "empty.wav")
    (tmp_path / "song.mp3").write_bytes(b"ID3\x03\x00" + bytes(200))
    with pytest.raises(AudioError, match=r"song\.mp3 is not a WAV file \(it does not start with a RIFF/WAVE"):
        load_audio(tmp_path / "song.mp3")
    with pytest.raises(AudioError, match=r"the audio is not a readable WAV file"):
        load_audio(b"RIFF\x10\x00\x00\x00WAVEjunkjunkjunk")
    with pytest.raises(AudioError, match="holds no audio samples"):
        load_audio(_wav_bytes(np.zeros(0, dtype=np.int16), RATE), name="upload")
    with pytest.raises(AudioError, match=r"is 50 ms long; an instruction needs at least 100 ms"):
        load_audio(_wav_bytes(_tone(RATE, 0.05).astype(np.int16), RATE))
    with pytest.raises(AudioError, match=r"is silent \(every sample is zero\)"):
        load_audio(_wav_bytes(np.zeros(RATE, dtype=np.int16), RATE))
    with pytest.raises(AudioError, match=r"is 61\.0 s long; instructions longer than 60 s"):
        to_16k_mono(np.ones(61 * 8000, dtype=np.int16), 8000)
    assert issubclass(AudioError, InstructionError)


# ---- pronunciations and grammar --------------------------------------------------------------------------
def test_letter_to_sound_hand_cases():
    cases = {
        "corridor": "K AO R IH D AO R",
        "white": "W AY T",
        "entrance": "EH N T R AE N S",
        "office": "AA F IH S",
        "kitchen": "K IH CH EH N",
        "storage": "S T AO R AE JH",
        "hall": "HH AE L",
        "city": "S IH T IY",
        "yard": "Y AA R D",
        "robolab": "R AA B AA L AE B",
    }
    for word, phones in cases.items():
        assert letter_to_sound(word) == phones, word
        assert set(phones.split()) <= PHONES
    with pytest.raises(ValueError, match="only the letters a-z"):
        letter_to_sound("キッチン")


def test_dictionary_pronunciations_reads_every_variant():
    lexicon = {"via": "V AY AH", "via(2)": "V IY AH", "to": "T UW"}
    assert dictionary_pronunciations("via", lexicon.get) == ["V AY AH", "V IY AH"]
    assert dictionary_pronunciations("to", lexicon.get) == ["T UW"]
    assert dictionary_pronunciations("robolab", lexicon.get) == []


def test_grammar_words_are_the_parsers():
    """Every phrase the recogniser may hear is read by the instruction grammar, in the role the JSGF gives it."""
    from spcotmhp.planning.instructions import parse_text

    for m in GOAL_MARKERS:
        assert parse_text(f"go {m} the kitchen", ["kitchen"]).goal.label == "kitchen", m
    for m in MARKERS:
        if m == "from":  # heard so that the parser can refuse it by name (a start place)
            with pytest.raises(InstructionError, match="'from' gives 'kitchen' as the start"):
                parse_text(f"go to the bedroom {m} the kitchen", ["kitchen", "bedroom"])
            continue
        ins = parse_text(f"go to the bedroom {m} the kitchen", ["kitchen", "bedroom"])
        assert ins.goal.label == "bedroom" and [q.label for q in (*ins.waypoints, *ins.avoid)] == ["kitchen"], m
    for c in CONNECTORS:
        ins = parse_text(f"go to the kitchen {c} the bedroom", ["kitchen", "bedroom"])
        assert [q.label for q in ins.stages] == ["kitchen", "bedroom"], c


def test_instruction_grammar_text_and_dropped_phrases():
    g = instruction_grammar(["kitchen", "bedroom", "kitchen"], lambda w: w != "navigate")
    assert g.place_words == ("bedroom", "kitchen")
    assert "<word> = bedroom | kitchen;" in g.jsgf
    assert "public <instruction> = [<polite>] <clause> <more>* [please];" in g.jsgf
    assert "<goal> = into | to | towards;" in g.jsgf
    assert g.dropped == ("navigate",) and "navigate" not in g.jsgf
    assert {"go", "via", "avoiding", "the"} <= set(g.grammar_words)
    with pytest.raises(ValueError, match="at least one place word"):
        instruction_grammar([], lambda w: True)
    with pytest.raises(ValueError, match="lower-case a-z words"):
        instruction_grammar(["Kitchen!"], lambda w: True)


# ---- the recogniser --------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def ps():
    return pytest.importorskip("pocketsphinx", reason="pocketsphinx (extra 'speech') is not installed")


def test_nbest_weights_group_paths_and_keep_grammatical_texts(ps):
    from spcotmhp.speech.recogniser import ASCALE, SENSCR_SHIFT, _weights

    k = 2**SENSCR_SHIFT / ASCALE
    paths = [
        ("go to the kitchen", -0.10),
        ("go to the kitchen", -0.11),
        ("go to the bedroom", -0.12),
        ("go to the", -0.01),
    ]
    out = _weights(paths, 5, lambda t: t != "go to the", "x")
    w_kitchen = np.logaddexp(-0.10 * k, -0.11 * k)
    expected = np.exp(w_kitchen - np.logaddexp(w_kitchen, -0.12 * k))
    assert [t for t, _ in out] == ["go to the kitchen", "go to the bedroom"]
    assert out[0][1] == pytest.approx(expected) and sum(w for _, w in out) == pytest.approx(1.0)
    assert _weights(paths, 1, lambda t: True, "x") == [("go to the", 1.0)]  # none rejected -> the best path
    assert next(t for t, _ in _weights(paths, 5, lambda t: False, "x")) == "go to the"  # none grammatical
    with pytest.raises(InstructionError, match="no instruction was recognised in clip.wav"):
        _weights([], 5, lambda t: True, "clip.wav")


def test_recogniser_errors(ps):
    from spcotmhp.speech import Recogniser, SpeechWarning

    with pytest.raises(InstructionError, match="supports lang='en' only, not 'ja'"):
        Recogniser(PLACES, lang="ja")
    with pytest.raises(InstructionError, match="none of the place words can be spoken .*: キッチン, 寝室"):
        Recogniser(["キッチン", "寝室"])
    with pytest.raises(
        InstructionError,
        match=r"no pronunciation for place word\(s\) robolab, zork in the "
        r"recogniser's dictionary",
    ):
        Recogniser(["kitchen", "zork", "robolab"], unknown="error")
    with pytest.warns(SpeechWarning, match=r"cannot listen for 1 place word\(s\) that are not a-z words: 寝室"):
        rec = Recogniser(["kitchen", "寝室"])
    assert rec.skipped == ("寝室",) and rec.grammar.place_words == ("kitchen",)
    with pytest.raises(ValueError, match="nbest must be >= 1"):
        rec.recognise(np.zeros(RATE, dtype=np.int16), nbest=0)
    with pytest.raises(AudioError, match="1-d int16 array at 16 kHz"):
        rec.recognise(np.zeros(RATE, dtype=np.float32))


def test_unknown_place_words_get_spelling_pronunciations(ps):
    from spcotmhp.speech import Recogniser

    rec = Recogniser(["kitchen", "robolab", "corridor"])
    assert rec.spelled == ("robolab",)
    lookup = rec._decoder.lookup_word
    assert lookup("robolab") == "R AA B AA L AE B"
    assert dictionary_pronunciations("corridor", lookup) == [
        "K AO R AH D ER",
        "K AO R IH D ER",
        "K AO R IH D AO R",
    ]
    plain = Recogniser(["corridor"], spelling_variants=False)
    assert dictionary_pronunciations("corridor", plain._decoder.lookup_word) == [
        "K AO R AH D ER",
        "K AO R IH D ER",
    ]


# ---- recognition of synthesised speech -------------------------------------------------------------------
@pytest.fixture(scope="module")
def espeak():
    exe = shutil.which("espeak-ng")
    if exe is None:
        pytest.skip("espeak-ng is not installed (apt-get install espeak-ng; `make system-deps` does it)")
    return exe


def synthesise(espeak: str, text: str, voice: str = "en-us") -> bytes:
    return subprocess.run([espeak, "-v", voice, "--stdout", text], capture_output=True, check=True).stdout


@pytest.fixture(scope="module")
def wavs(espeak, tmp_path_factory):
    folder = tmp_path_factory.mktemp("speech")
    paths = []
    for i, (text, _) in enumerate(INSTRUCTIONS):
        path = folder / f"instruction{i:02d}.wav"
        path.write_bytes(synthesise(espeak, text))
        paths.append(path)
    return paths


def understood(hypotheses) -> tuple:
    """(goal, waypoints, avoid): the top word of each bag of the planner's N-best parse (Eq. 25)."""
    ins = parse_nbest(hypotheses, PLACES, lang="en")

    def top(q):
        return max(q.words, key=q.words.get)

    return top(ins.goal), tuple(top(w) for w in ins.waypoints), tuple(top(a) for a in ins.avoid)


def test_recognition_accuracy_on_espeak_instructions(ps, wavs):
    from spcotmhp.speech import recognise

    right, wrong = 0, []
    for path, (text, expected) in zip(wavs, INSTRUCTIONS, strict=False):
        hyps = recognise(path, PLACES, lang="en", nbest=5)
        weights = [w for _, w in hyps]
        assert 1 <= len(hyps) <= 5 and sum(weights) == pytest.approx(1.0)
        assert weights == sorted(weights, reverse=True) and min(weights) > 0
        got = understood(hyps)
        right += got == expected
        if got != expected:
            wrong.append((text, hyps[0][0], got))
    assert right >= 0.9 * len(INSTRUCTIONS), (
        f"{right}/{len(INSTRUCTIONS)} espeak-ng instructions with the right goal and waypoints; wrong: {wrong}"
    )


def test_recognition_of_44k_stereo_audio(ps, espeak):
    from spcotmhp.speech import recognise

    mono, rate, _ = read_wav(synthesise(espeak, INSTRUCTIONS[0][0]))
    up = np.interp(np.arange(0, len(mono), rate / 44100), np.arange(len(mono)), mono.astype(float))
    stereo = np.stack([up, 0.5 * up], axis=1).astype(np.int16)
    hyps = recognise(_wav_bytes(stereo, 44100), PLACES)
    assert understood(hyps) == INSTRUCTIONS[0][1]


def test_noise_is_not_an_instruction(ps):
    from spcotmhp.speech import recognise

    noise = np.random.default_rng(1).normal(0, 3000, RATE).astype(np.int16)
    try:
        hyps = recognise(_wav_bytes(noise, RATE), PLACES)
    except InstructionError as exc:
        assert "no instruction was recognised" in str(exc)
    else:  # the grammar forces some sentence; it must still be a well-formed N-best list
        assert sum(w for _, w in hyps) == pytest.approx(1.0)


def test_spoken_instruction_plans_on_the_learned_3ldk_06(ps, espeak, tmp_path):
    from spcotmhp.datasets import load_bundled
    from spcotmhp.learning.supervised import fit_supervised
    from spcotmhp.planning.planner import HierarchicalPlanner
    from spcotmhp.speech import recognise_for_model

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = fit_supervised(load_bundled("3LDK_06", lang="en"))
    wav = tmp_path / "say.wav"
    wav.write_bytes(synthesise(espeak, "go to the bedroom via the corridor"))
    hyps = recognise_for_model(wav, model)
    plan = HierarchicalPlanner(model).plan(hyps, start=(1.4, -1.1))  # in the dining room
    roles = [(p.role, p.name) for p in plan.places]
    assert ("waypoint", "corridor") in roles and roles[-1] == ("goal", "bedroom")
    assert roles.index(("waypoint", "corridor")) < len(roles) - 1


def test_missing_pocketsphinx_is_a_clear_error(monkeypatch):
    import builtins

    from spcotmhp.speech import recogniser

    real_import = builtins.__import__

    def fake_import(name, *args, **kwargs):
        if name == "pocketsphinx":
            raise ImportError("no pocketsphinx")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", fake_import)
    with pytest.raises(
        SpcotmhpError,
        match=r"speech input \(pocketsphinx\) needs the extra 'speech': \S+ -m pip "
        r"install -e '\S*\[speech\]'",
    ):
        recogniser._pocketsphinx()


# ---- spcotmhp plan --audio -------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def model_folder(tmp_path_factory):
    from spcotmhp.datasets import load_bundled
    from spcotmhp.learning.supervised import fit_supervised
    from spcotmhp.persistence.io import save_model

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = fit_supervised(load_bundled("3LDK_06", lang="en"))
    return save_model(model, tmp_path_factory.mktemp("model") / "3LDK_06")


def _plan_cli(*args: str, env: dict | None = None) -> subprocess.CompletedProcess:
    import os
    import sys
    from pathlib import Path

    exe = str(Path(sys.executable).with_name("spcotmhp"))
    return subprocess.run(
        [exe, "plan", *args],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
        env=None if env is None else {**os.environ, **env},
    )


def test_plan_cli_from_a_wav_file(ps, espeak, model_folder, tmp_path):
    wav = tmp_path / "say.wav"
    wav.write_bytes(synthesise(espeak, "go to the bedroom via the corridor"))
    out = _plan_cli(str(model_folder), "--audio", str(wav), "--start", "-3.9", "-3.5")
    assert out.returncode == 0, out.stderr
    heard = [line for line in out.stderr.splitlines() if line.startswith("heard: ")]
    assert 1 <= len(heard) <= 5 and heard[0].endswith(" go to the bedroom via the corridor")
    line = out.stdout.strip()
    assert line.startswith("entrance -> ") and "corridor (waypoint)" in line and "bedroom #" in line


@pytest.mark.parametrize(
    "args, message",
    [
        (
            ["go to the bath", "--audio", "{wav}"],
            ("give exactly one of INSTRUCTION, --nbest FILE or --audio FILE (got INSTRUCTION and --audio)"),
        ),
        (["--nbest", "{wav}", "--audio", "{wav}"], "(got --nbest and --audio)"),
    ],
)
def test_plan_cli_audio_usage_errors(model_folder, tmp_path, args, message):
    wav = tmp_path / "x.wav"
    wav.write_bytes(b"RIFF")
    out = _plan_cli(str(model_folder), *[a.format(wav=wav) for a in args], "--start", "0", "0")
    assert out.returncode == 2
    assert message in " ".join(out.stderr.replace("│", " ").split())


def test_plan_cli_audio_errors_are_one_line(model_folder, tmp_path):
    out = _plan_cli(str(model_folder), "--audio", str(tmp_path / "missing.wav"), "--start", "0", "0")
    assert out.returncode == 2 and out.stderr.strip() == (
        f"error: the audio file {tmp_path / 'missing.wav'} does not exist or is not a file"
    )
    fake = tmp_path / "fake"
    fake.mkdir()
    (fake / "pocketsphinx.py").write_text("raise ImportError('no pocketsphinx here')\n")
    wav = tmp_path / "x.wav"
    wav.write_bytes(_wav_bytes(_tone(RATE).astype(np.int16), RATE))
    import os  # the fake module first, then the spcotmhp under test

    path = os.pathsep.join([str(fake), *filter(None, [os.environ.get("PYTHONPATH")])])
    out = _plan_cli(str(model_folder), "--audio", str(wav), "--start", "0", "0", env={"PYTHONPATH": path})
    assert out.returncode == 2
    message = out.stderr.strip()  # from this source tree: an editable install of the extra
    assert message.startswith("error: speech input (pocketsphinx) needs the extra 'speech': ") and "\n" not in message
    assert " -m pip install -e '" in message and message.endswith("[speech]'")
