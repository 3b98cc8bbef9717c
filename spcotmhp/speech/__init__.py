"""Spoken instructions: WAV audio -> N-best hypotheses [(text, weight)] for the planner (Eq. 25).

``recognise(wav, vocabulary)`` runs pocketsphinx (extra ``speech``) constrained by a grammar built from the
place words and the English instruction grammar; ``recognise_for_model(wav, model)`` takes the place words
from a learned model; ``Recogniser`` keeps one decoder for repeated calls (a server).
"""

from __future__ import annotations

from typing import Any

from spcotmhp.speech.audio import AudioError, AudioSource, load_audio
from spcotmhp.speech.recogniser import Recogniser, SpeechWarning, cached_recogniser, recognise


def recognise_for_model(audio: AudioSource, model: Any, nbest: int = 5) -> list[tuple[str, float]]:
    """N-best hypotheses for ``audio`` with the grammar built from ``model``'s place words
    (:func:`spcotmhp.planning.vocabulary.place_vocabulary`); pass the result to the planner as the
    instruction (``HierarchicalPlanner.plan(hypotheses, start)``), which weighs the bags of words by it."""
    from spcotmhp.planning.vocabulary import place_vocabulary

    return cached_recogniser(tuple(place_vocabulary(model)), "en").recognise(audio, nbest)


__all__ = [
    "AudioError",
    "AudioSource",
    "Recogniser",
    "SpeechWarning",
    "cached_recogniser",
    "load_audio",
    "recognise",
    "recognise_for_model",
]
