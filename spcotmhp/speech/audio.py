"""WAV input for the recogniser: any PCM or float WAV -> 16 kHz mono 16-bit samples.

pocketsphinx's en-us acoustic model expects 16 kHz, mono, 16-bit audio. Other inputs are converted:

* channels are averaged into one;
* 8-bit (unsigned), 24- and 32-bit integer and 32/64-bit float samples are scaled to the 16-bit range;
* other sample rates are resampled with ``scipy.signal.resample_poly`` (polyphase FIR with a Kaiser-window
  anti-aliasing filter) by the exact ratio 16000 / rate. Audio below 16 kHz (e.g. 8 kHz telephone audio)
  is upsampled but has no energy above its own Nyquist frequency, so expect lower accuracy;
* a seeded Gaussian noise floor of :data:`NOISE_FLOOR` (about -72 dBFS) is added. Exactly-zero stretches
  (synthesised or gated audio) otherwise give log(0) filterbank energies that derail pocketsphinx's noise
  removal and cepstral mean normalisation; the floor is far below any microphone's own noise.
"""

from __future__ import annotations

import io
import math
import warnings
from pathlib import Path
from typing import BinaryIO

import numpy as np
from scipy.io import wavfile
from scipy.signal import resample_poly

from spcotmhp.errors import InstructionError

RATE = 16_000
NOISE_FLOOR = 8.0  # standard deviation in 16-bit units: 20 log10(8 / 32768) = -72 dBFS
MIN_SECONDS = 0.1
MAX_SECONDS = 60.0

AudioSource = str | Path | bytes | BinaryIO


class AudioError(InstructionError):
    """The audio of a spoken instruction is missing, not a WAV file, empty, silent or too long."""


def read_wav(source: AudioSource, name: str | None = None) -> tuple[np.ndarray, int, int]:
    """The raw samples of a WAV file: (samples (n,) or (n, channels), sample rate, channels).

    ``source`` is a path, the file's bytes, or a binary file object; ``name`` labels it in messages.
    """
    label = name or (str(source) if isinstance(source, (str, Path)) else "the audio")
    if isinstance(source, (str, Path)):
        path = Path(source)
        if not path.is_file():
            raise AudioError(f"audio file {path} does not exist")
        data = path.read_bytes()
    elif isinstance(source, (bytes, bytearray)):
        data = bytes(source)
    else:
        data = source.read()
    if not data:
        raise AudioError(f"{label} is empty (0 bytes); expected a WAV file")
    if data[:4] != b"RIFF" or data[8:12] != b"WAVE":
        raise AudioError(
            f"{label} is not a WAV file (it does not start with a RIFF/WAVE header); "
            "record or convert to WAV, ideally 16 kHz mono 16-bit"
        )
    try:
        with warnings.catch_warnings():  # a streamed WAV (from a pipe) has a placeholder length: read what is there
            warnings.simplefilter("ignore", wavfile.WavFileWarning)
            rate, samples = wavfile.read(io.BytesIO(data))
    except Exception as exc:  # noqa: BLE001 - scipy raises many types on malformed files (even UnboundLocalError)
        raise AudioError(f"{label} is not a readable WAV file: {exc}") from None
    channels = 1 if samples.ndim == 1 else samples.shape[1]
    return samples, int(rate), channels


def to_16k_mono(samples: np.ndarray, rate: int, label: str = "the audio") -> np.ndarray:
    """Convert samples at ``rate`` (module docstring) to int16 mono at 16 kHz with the noise floor added.

    Raises:
        AudioError: no samples, shorter than 0.1 s or longer than 60 s, or silent (every sample zero).
    """
    if rate <= 0:
        raise AudioError(f"{label} has an invalid sample rate {rate} Hz")
    x = _as_float(samples)
    if x.ndim == 2:
        x = x.mean(axis=1)
    seconds = len(x) / rate
    if len(x) == 0:
        raise AudioError(f"{label} holds no audio samples")
    if seconds < MIN_SECONDS:
        raise AudioError(
            f"{label} is {seconds * 1000:.0f} ms long; an instruction needs at least "
            f"{MIN_SECONDS * 1000:.0f} ms of speech"
        )
    if seconds > MAX_SECONDS:
        raise AudioError(
            f"{label} is {seconds:.1f} s long; instructions longer than {MAX_SECONDS:.0f} s are not accepted"
        )
    if not np.any(x):
        raise AudioError(f"{label} is silent (every sample is zero)")
    if rate != RATE:
        g = math.gcd(RATE, rate)
        x = resample_poly(x, RATE // g, rate // g)
    x = x + np.random.default_rng(0).normal(0.0, NOISE_FLOOR, len(x))
    return np.clip(np.rint(x), -32768, 32767).astype(np.int16)


def load_audio(source: AudioSource, name: str | None = None) -> np.ndarray:
    """Read a WAV file and return 16 kHz mono int16 samples ready for the recogniser."""
    samples, rate, _ = read_wav(source, name)
    return to_16k_mono(samples, rate, name or (str(source) if isinstance(source, (str, Path)) else "the audio"))


def _as_float(samples: np.ndarray) -> np.ndarray:
    """Samples on the 16-bit scale as float64 (8-bit WAV is unsigned, centred on 128)."""
    kind, size = samples.dtype.kind, samples.dtype.itemsize
    x = samples.astype(np.float64)
    if kind == "u" and size == 1:
        return (x - 128.0) * 256.0
    if kind == "i":
        return x * (32768.0 / 2.0 ** (8 * size - 1))
    if kind == "f":
        return x * 32767.0
    raise AudioError(f"unsupported WAV sample type {samples.dtype}")
