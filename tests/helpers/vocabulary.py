"""The place words of the bundled SIGVerse homes' instructions, in English and Japanese (one list for every test
that builds instructions from them)."""

from __future__ import annotations

PLACE_WORDS_EN = [
    "entrance",
    "living",
    "dining",
    "kitchen",
    "bath",
    "washroom",
    "toilet",
    "bedroom",
    "storeroom",
    "corridor",
    "hall",
]
PLACE_WORDS_JA = [
    "玄関",
    "リビング",
    "ダイニング",
    "キッチン",
    "風呂",
    "洗面所",
    "トイレ",
    "寝室",
    "物置き",
    "廊下",
    "広場",
]
