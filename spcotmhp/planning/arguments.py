"""Checks of the arguments of the instruction parsers (``parse_text``, ``parse_structured``, ``parse_nbest``):
a caller's mistake is a one-line typed error naming the argument, before any parsing.
"""

from __future__ import annotations

from typing import Any

from spcotmhp.errors import InvalidSettings, MalformedInstruction
from spcotmhp.limits import is_count
from spcotmhp.safe_read import excerpt


def check_parse_arguments(function: str, place_words: Any, **limits: Any) -> None:
    """``place_words`` must be a collection of words (a single string is refused: it would be read as its
    letters); each limit None or an integer >= 0 (MalformedInstruction / InvalidSettings naming ``function``)."""
    if isinstance(place_words, str):
        raise MalformedInstruction(
            f"{function}: place_words must be a list of words, not one string ({excerpt(place_words, 30)}); "
            f"give [{excerpt(place_words, 30)}]"
        )
    for name, value in limits.items():
        if value is None:
            continue
        if not is_count(value) or value < 0:
            raise InvalidSettings(f"{function}: {name} must be an integer >= 0 or None (the default), got {value!r}")


def check_keywords(function: str, given: dict[str, Any], accepted: tuple[str, ...]) -> None:
    """TypeError naming ``function`` and its accepted keyword arguments when ``given`` holds others."""
    unknown = [k for k in given if k not in accepted]
    if unknown:
        raise TypeError(
            f"{function}() got unexpected keyword argument(s) {', '.join(repr(k) for k in unknown[:5])}; "
            f"accepted: {', '.join(accepted)}"
        )
