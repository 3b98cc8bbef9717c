"""Speech recognition of navigation instructions with pocketsphinx, constrained by the learned place words.

The decoder searches only the sentences of :mod:`spcotmhp.speech.jsgf`'s grammar, with pronunciations from
:mod:`spcotmhp.speech.lexicon`. Its N-best list becomes weighted hypotheses [(text, weight)], the Monte Carlo
form of the word observations S in Eq. 25 (Taniguchi et al. 2024, Section 3.3: "capturing the N-best speech
recognition results"), which :func:`spcotmhp.planning.instructions.parse_nbest` turns into weighted bags of
words for the planner.

Weights. pocketsphinx's A* N-best search gives each path a log score in its log base (1.0001) whose acoustic
part is scaled down by 2**10 (SENSCR_SHIFT). A path's posterior is approximated as it does for confidences:
log w = ln(score) * 2**10 / ascale with ascale = 20 (pocketsphinx's default acoustic scale). Paths with the same
words (different alignments or pronunciations) are summed; hypotheses that the grammar does not accept
(a path that ran out of audio mid-sentence) are dropped unless none is accepted; the best ``nbest`` are kept and
their weights normalised to sum to 1.
"""

from __future__ import annotations

import threading
import warnings
from collections.abc import Iterable
from functools import lru_cache

import numpy as np

from spcotmhp.errors import EmptyInstruction, SpcotmhpError, UnknownPlaceWord, UnsupportedLanguage
from spcotmhp.extras import missing_extra
from spcotmhp.logspace import logsumexp
from spcotmhp.speech.audio import AudioError, AudioSource, load_audio
from spcotmhp.speech.jsgf import InstructionGrammar, instruction_grammar
from spcotmhp.speech.lexicon import SPEAKABLE, dictionary_pronunciations, letter_to_sound

SENSCR_SHIFT = 10
ASCALE = 20.0
SCAN = 200  # N-best paths read from the lattice (many share their words)


class SpeechWarning(UserWarning):
    """Place words the recogniser cannot listen for (not Latin letters)."""


class Recogniser:
    """A pocketsphinx decoder for one vocabulary (build once, call :meth:`recognise` per utterance; thread-safe).

    Args:
        vocabulary: the place words (e.g. :func:`spcotmhp.planning.vocabulary.place_vocabulary` of a model).
        lang: "en" only (the pocketsphinx wheel ships an en-us acoustic model and CMUdict).
        unknown: place words missing from CMUdict: "spell" gives them letter-to-sound pronunciations,
            "error" rejects them with an UnknownPlaceWord error naming each.
        spelling_variants: add the spelling pronunciation of every place word (module docstring of
            :mod:`spcotmhp.speech.lexicon`).
    """

    def __init__(
        self,
        vocabulary: Iterable[str],
        lang: str = "en",
        unknown: str = "spell",
        spelling_variants: bool = True,
    ) -> None:
        if lang != "en":
            raise UnsupportedLanguage(
                f"speech recognition supports lang='en' only, not {lang!r}: the pocketsphinx "
                "wheel ships an English (en-us) acoustic model and dictionary"
            )
        if unknown not in ("spell", "error"):
            raise ValueError(f"unknown must be 'spell' or 'error', got {unknown!r}")
        decoder_cls, config_cls = _pocketsphinx()
        self._decoder = decoder_cls(config_cls(lm=None, loglevel="FATAL"))
        words = sorted({w.lower() for w in vocabulary})
        speakable = [w for w in words if SPEAKABLE.fullmatch(w)]
        self.skipped = tuple(w for w in words if not SPEAKABLE.fullmatch(w))
        if not speakable:
            raise UnsupportedLanguage(
                "none of the place words can be spoken to the English recogniser (it needs words of the letters "
                f"a-z): {', '.join(self.skipped[:20]) or 'the vocabulary is empty'}"
            )
        if self.skipped:
            warnings.warn(
                SpeechWarning(
                    f"the recogniser cannot listen for {len(self.skipped)} place word(s) that "
                    f"are not a-z words: {', '.join(self.skipped[:20])}"
                ),
                stacklevel=2,
            )
        self.spelled = self._add_pronunciations(speakable, unknown, spelling_variants)
        lookup = self._decoder.lookup_word
        self.grammar: InstructionGrammar = instruction_grammar(speakable, lambda w: lookup(w) is not None)
        self._decoder.add_jsgf_string("instruction", self.grammar.jsgf)
        self._decoder.activate_search("instruction")
        self._fsg = self._decoder.get_fsg("instruction")
        self._lock = threading.Lock()

    def _add_pronunciations(self, words: list[str], unknown: str, variants: bool) -> tuple[str, ...]:
        """Give every place word its spelling pronunciation where CMUdict lacks it or (``variants``) as an
        alternative; returns the words that had no dictionary pronunciation."""
        lookup = self._decoder.lookup_word
        missing = [w for w in words if lookup(w) is None]
        if missing and unknown == "error":
            raise UnknownPlaceWord(
                f"no pronunciation for place word(s) {', '.join(missing)} in the recogniser's "
                "dictionary (CMUdict); use unknown='spell' for letter-to-sound pronunciations"
            )
        for w in words:
            known = dictionary_pronunciations(w, lookup)
            if known and not variants:
                continue
            spelled = letter_to_sound(w)
            if spelled and spelled not in known:
                self._decoder.add_word(f"{w}({len(known) + 1})" if known else w, spelled, True)
        return tuple(missing)

    def recognise(
        self, audio: AudioSource | np.ndarray, nbest: int = 5, name: str | None = None
    ) -> list[tuple[str, float]]:
        """N-best hypotheses [(text, weight)] for a WAV file / bytes / file object, or 16 kHz mono int16
        samples; weights are > 0, sum to 1, best first.

        Raises:
            AudioError: not a WAV file, empty, silent or too long. EmptyInstruction: nothing was recognised.
        """
        if nbest < 1:
            raise ValueError(f"nbest must be >= 1, got {nbest}")
        samples = audio if isinstance(audio, np.ndarray) else load_audio(audio, name)
        if samples.dtype != np.int16 or samples.ndim != 1:
            raise AudioError("samples must be a 1-d int16 array at 16 kHz (use spcotmhp.speech.load_audio)")
        with self._lock:
            d = self._decoder
            d.start_utt()
            d.process_raw(samples.tobytes(), no_search=False, full_utt=True)
            d.end_utt()
            best = d.hyp()
            paths = []
            for i, h in enumerate(d.nbest() or ()):
                if i >= SCAN:
                    break
                if h is not None and h.hypstr and h.score > 0:
                    paths.append((h.hypstr, float(np.log(h.score))))
        if best is not None and best.hypstr and not paths:
            paths.append((best.hypstr, 0.0))
        return _weights(paths, nbest, self._fsg.accept, name or "the audio")


def _weights(paths: list[tuple[str, float]], nbest: int, accept, label: str) -> list[tuple[str, float]]:
    """Group paths by text, sum their posteriors, keep grammatical texts (if any) and the best ``nbest``."""
    if not paths:
        raise EmptyInstruction(f"no instruction was recognised in {label} (no speech matching the grammar)")
    texts = sorted({t for t, _ in paths})
    scaled = np.array([s for _, s in paths]) * (2**SENSCR_SHIFT / ASCALE)
    index = {t: i for i, t in enumerate(texts)}
    groups = np.array([index[t] for t, _ in paths])
    logw = np.array([logsumexp(scaled[groups == i]) for i in range(len(texts))])
    ok = np.array([bool(accept(t)) for t in texts])
    if ok.any():
        logw[~ok] = -np.inf
    order = [i for i in np.argsort(-logw, kind="stable") if np.isfinite(logw[i])][:nbest]
    w = np.exp(logw[order] - logsumexp(logw[order]))
    return [(texts[i], float(x)) for i, x in zip(order, w, strict=False)]


def _pocketsphinx():
    try:
        from pocketsphinx import Config, Decoder
    except ImportError:
        raise SpcotmhpError(missing_extra("speech input (pocketsphinx)", "speech")) from None
    return Decoder, Config


@lru_cache(maxsize=8)
def cached_recogniser(vocabulary: tuple[str, ...], lang: str = "en", unknown: str = "spell") -> Recogniser:
    """A :class:`Recogniser` per (vocabulary, lang, unknown), built once per process."""
    return Recogniser(vocabulary, lang, unknown)


def recognise(
    wav_path: AudioSource, vocabulary: Iterable[str], lang: str = "en", nbest: int = 5
) -> list[tuple[str, float]]:
    """Recognise a spoken instruction: N-best [(text, weight)], best first, weights summing to 1.

    ``vocabulary`` is the list of place words the grammar accepts (see :class:`Recogniser`).
    """
    return cached_recogniser(tuple(sorted(set(vocabulary))), lang).recognise(wav_path, nbest)
