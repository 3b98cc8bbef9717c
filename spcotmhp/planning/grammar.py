"""Grammar words of navigation instructions, one small table per language.

The place words of an instruction are whatever the learned vocabulary holds (on-site names, any language); this
module only lists the closed-class words that say what role a named place plays:

* ``goal``: where the robot must end ("to", "into"; へ, に行って).
* ``waypoint``: a place to pass on the way, in the order spoken ("via", "through", "passing by"; を通って, 経由して).
* ``avoid``: a place the path must not enter ("avoiding", "without passing", "not through"; を避けて, を通らずに).
* ``from``: the place the robot starts in ("from"; から). The start is the pose given to the planner, so such a
  phrase is parsed and then ignored.

``attach`` says on which side of its place phrase a marker stands: English markers are prepositions (``prefix``:
"via the corridor"), Japanese ones are postpositions (``postfix``: 廊下を通って). ``connectors`` ("and", "then", と)
let the next phrase share a role ("avoiding the living and the kitchen"; トイレとダイニングを経由して).
English is matched on lower-cased word tokens, Japanese on characters (no spaces needed); the longest table
entry wins, and a place word wins over a grammar word of the same length.
"""

from __future__ import annotations

from dataclasses import dataclass

ROLES = ("goal", "waypoint", "avoid", "from")


@dataclass(frozen=True)
class Grammar:
    """The grammar words of one language.

    Attributes:
        lang: language code ("en", "ja").
        attach: "prefix" (marker before its place phrase) or "postfix" (marker after it).
        markers: phrase -> role, phrases as written (English: space-separated words).
        connectors: phrases that continue the previous role.
        fillers: words that carry no meaning for the parse. English: skipped, and not reported as "not
            understood". Every language: never taken as place words unless a word is some place's best name
            (:func:`~spcotmhp.planning.vocabulary.place_vocabulary`).
        by_character: match on characters (Japanese) instead of whitespace/punctuation-separated words.
    """

    lang: str
    attach: str
    markers: dict[str, str]
    connectors: frozenset[str]
    fillers: frozenset[str] = frozenset()
    by_character: bool = False


def _roles(**groups: tuple[str, ...]) -> dict[str, str]:
    return {phrase: role for role, phrases in groups.items() for phrase in phrases}


ENGLISH = Grammar(
    lang="en",
    attach="prefix",
    markers=_roles(
        goal=("to", "into", "toward", "towards", "reach", "until", "at"),
        waypoint=("via", "through", "thru", "passing", "passing by", "passing through", "pass by", "pass through",
                  "go through", "going through", "by way of", "past", "stopping at", "stop at", "stop by",
                  "visiting", "after visiting"),
        avoid=("avoid", "avoiding", "avoids", "not", "not through", "not via", "not passing", "not passing by",
               "not passing through", "without", "without passing", "without passing by", "without passing through",
               "without going through", "without entering", "don't go through", "do not go through",
               "don't pass", "don't pass through", "do not pass", "do not pass through", "don't enter",
               "do not enter", "except", "but not", "bypass", "bypassing", "skip", "skipping", "stay out of",
               "keep out of", "away from"),
        **{"from": ("from", "starting from", "leaving")},
    ),
    connectors=frozenset({"and", "then", "and then", "after that", "afterwards", "next", "finally", "first", "or",
                          ",", ";", "&"}),
    fillers=frozenset({"the", "a", "an", "my", "our", "your", "this", "that", "please", "go", "goes", "going",
                       "take", "me", "us", "bring", "get", "head", "move", "navigate", "drive", "walk", "come",
                       "lead", "guide", "can", "could", "would", "you", "i", "we", "it", "want", "need", "let's",
                       "let", "room", "place", "area", "way", "there", "here", "now", "robot", "hey", "ok", "okay",
                       "again", "back", "along", "of", "all", "by", "on", "in", "side", "pass", "enter", "visit",
                       "is", "are", "am", "be", "called", "name", "named", "this's", "um", "uh", "so", "well",
                       "look"}),
)

JAPANESE = Grammar(
    lang="ja",
    attach="postfix",
    markers=_roles(
        goal=("へ", "に", "まで", "へ行って", "に行って", "まで行って", "へいって", "にいって", "までいって",
              "へ行く", "に行く", "へいく", "にいく", "に連れて行って", "につれていって", "へ連れて行って",
              "へつれていって", "に向かって", "へ向かって", "にむかって", "へむかって", "に移動して", "へ移動して",
              "行って", "いって"),
        waypoint=("を通って", "をとおって", "通って", "とおって", "を経由して", "経由して", "をけいゆして", "けいゆして",
                  "経由で", "けいゆで", "を通り", "をとおり", "を通過して", "に寄って", "によって", "へ寄って",
                  "を回って", "をまわって"),
        avoid=("を避けて", "をさけて", "避けて", "さけて", "を通らずに", "をとおらずに", "を通らないで", "をとおらないで",
               "を通らず", "をとおらず", "を経由せずに", "をけいゆせずに", "に入らずに", "にはいらずに", "に入らないで",
               "にはいらないで", "に寄らずに", "によらずに", "以外", "いがい", "を除いて", "をのぞいて"),
        **{"from": ("から",)},
    ),
    connectors=frozenset({"と", "、", ",", "，", "それから", "そして", "その後", "そのあと", "や"}),
    fillers=frozenset({"ここ", "ここが", "ここは", "ここわ", "こちら", "こちらが", "この", "ここの", "です", "だよ",
                       "だ", "になります", "にきました", "ください", "ロボット", "このばしょ", "このばしょが",
                       "このばしょは", "このばしょわ", "このばしょの", "このばしょのなまえは", "このばしょのなまえわ",
                       "ここのなまえは", "ここのなまえわ", "なまえ", "わこちらです", "はこちらです"}),
    by_character=True,
)

GRAMMARS: dict[str, Grammar] = {"en": ENGLISH, "ja": JAPANESE}
"""The grammar of each supported language; add a language by adding a table here."""
