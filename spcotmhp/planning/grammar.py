"""Grammar words of navigation instructions, one small table per language.

The place words of an instruction are whatever the learned vocabulary holds (on-site names, any language); this
module only lists the closed-class words that say what role a named place plays:

* ``goal``: where the robot must end ("to", "into"; へ, に行って).
* ``waypoint``: a place to pass on the way, in the order spoken ("via", "through", "passing by"; を通って, 経由して).
* ``avoid``: a place the path must not enter ("avoiding", "without passing", "not through", and negations of going
  there: "don't go to", "never pass"; を避けて, を通らずに, に行かないで, は通らないで). A negation followed by
  other markers with only fillers between ("I don't want to go to the kitchen") keeps the avoid role.
* ``not_goal``: a place that must not be the goal but may be passed ("instead of", "rather than"; ではなく,
  の代わりに). "Go to the bedroom instead of the kitchen" corrects the destination; nothing in it forbids
  driving through the kitchen, so the kitchen is not avoided, only never chosen as the goal.
* ``from``: the place the robot starts in ("from"; から). The start is the pose given to the planner, so such a
  phrase is parsed and then ignored.

Two kinds of phrases are recognised only to be refused (the parser raises an error saying why rather than
guessing): ``alternatives`` ("or", "either"; または) leave the choice of a place open, and ``relations``
("next to", "near", "behind"; の隣, の近く) describe a place by a spatial relation to another, which the model
does not represent.

``attach`` says on which side of its place phrase a marker stands: English markers are prepositions (``prefix``:
"via the corridor"), Japanese ones are postpositions (``postfix``: 廊下を通って). ``connectors`` ("and", "then", と)
let the next phrase share a role ("avoiding the living and the kitchen"; トイレとダイニングを経由して).
English is matched on lower-cased word tokens, Japanese on characters (no spaces needed); the longest table
entry wins, and a place word wins over a grammar word of the same length.
"""

from __future__ import annotations

from dataclasses import dataclass, field

ROLES = ("goal", "waypoint", "avoid", "not_goal", "from")


@dataclass(frozen=True)
class Grammar:
    """The grammar words of one language.

    Attributes:
        lang: language code ("en", "ja").
        attach: "prefix" (marker before its place phrase) or "postfix" (marker after it).
        markers: phrase -> role, phrases as written (English: space-separated words).
        connectors: phrases that continue the previous role.
        soft_connectors: the connectors that are only punctuation (",", 、): unknown words after them are
            reported only when they follow a determiner ("go to the kitchen, thanks" is fine, "go to the kitchen,
            the attic" is not).
        determiners: fillers that open a noun phrase ("the", "my").
        alternatives: phrases offering a choice between places ("or"), refused.
        relations: spatial relations between places ("next to"), refused.
        between_places: short words that mean something only when they stand alone between two place
            phrases (Japanese: の joins them into one name, 玄関の廊下; か offers alternatives, キッチンかトイレ):
            word -> "join" or "alternative". Elsewhere they are ordinary characters of other words.
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
    soft_connectors: frozenset[str] = frozenset()
    determiners: frozenset[str] = frozenset()
    alternatives: frozenset[str] = frozenset()
    relations: frozenset[str] = frozenset()
    between_places: dict[str, str] = field(default_factory=dict)


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
               "keep out of", "away from", "don't", "dont", "do not", "never", "don't go to", "do not go to",
               "don't go into", "do not go into", "never go to", "never go into", "never go through", "never pass",
               "never pass by", "never pass through", "never enter", "never visit", "don't visit", "do not visit",
               "not to", "not into", "not via", "without going to", "without visiting"),
        not_goal=("instead of", "rather than"),
        **{"from": ("from", "starting from", "leaving")},
    ),
    connectors=frozenset({"and", "then", "and then", "after that", "afterwards", "next", "finally", "first",
                          ",", ";", "&"}),
    soft_connectors=frozenset({",", ";"}),
    determiners=frozenset({"the", "a", "an", "my", "our", "your", "this", "that"}),
    alternatives=frozenset({"or", "either", "or else", "whichever"}),
    relations=frozenset({"next to", "near", "near to", "nearby", "close to", "beside", "behind", "in front of",
                         "opposite", "opposite to", "across from", "between", "left of", "right of", "above",
                         "below", "beyond"}),
    fillers=frozenset({"the", "a", "an", "my", "our", "your", "this", "that", "please", "go", "goes", "going",
                       "take", "me", "us", "bring", "get", "head", "move", "navigate", "drive", "walk", "come",
                       "lead", "guide", "can", "could", "would", "you", "i", "we", "it", "want", "need", "let's",
                       "let", "room", "place", "area", "way", "there", "here", "now", "robot", "hey", "ok", "okay",
                       "again", "back", "along", "of", "all", "by", "on", "in", "side", "pass", "enter", "visit",
                       "is", "are", "am", "be", "called", "name", "named", "this's", "um", "uh", "so", "well",
                       "look", "once", "quickly", "slowly", "carefully", "thanks", "thank", "immediately", "soon",
                       "right", "away", "straight"}),
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
               "にはいらないで", "に寄らずに", "によらずに", "以外", "いがい", "を除いて", "をのぞいて",
               "に行かないで", "へ行かないで", "には行かないで", "へは行かないで", "に行かずに", "へ行かずに",
               "にいかないで", "へいかないで", "にはいかないで", "にいかずに", "行かないで", "いかないで",
               "入らないで", "はいらないで", "には入らないで", "には入らずに", "は通らないで", "はとおらないで",
               "は通らずに", "はとおらずに", "を通らないでください", "は避けて", "はさけて"),
        not_goal=("ではなく", "ではなくて", "じゃなく", "じゃなくて", "の代わりに", "のかわりに", "ではなしに"),
        **{"from": ("から",)},
    ),
    connectors=frozenset({"と", "、", ",", "，", "それから", "そして", "その後", "そのあと", "や"}),
    soft_connectors=frozenset({"、", ",", "，"}),
    alternatives=frozenset({"または", "もしくは", "あるいは", "それとも"}),
    between_places={"の": "join", "か": "alternative"},
    relations=frozenset({"の隣", "のとなり", "の近く", "のちかく", "の横", "のよこ", "の前", "のまえ", "の後ろ",
                         "のうしろ", "の向かい", "のむかい", "のそば", "の奥", "のおく", "の間", "のあいだ"}),
    fillers=frozenset({"ここ", "ここが", "ここは", "ここわ", "こちら", "こちらが", "この", "ここの", "です", "だよ",
                       "だ", "になります", "にきました", "ください", "ロボット", "このばしょ", "このばしょが",
                       "このばしょは", "このばしょわ", "このばしょの", "このばしょのなまえは", "このばしょのなまえわ",
                       "ここのなまえは", "ここのなまえわ", "なまえ", "わこちらです", "はこちらです"}),
    by_character=True,
)

GRAMMARS: dict[str, Grammar] = {"en": ENGLISH, "ja": JAPANESE}
"""The grammar of each supported language; add a language by adding a table here."""
