"""Grammar words of navigation instructions, one small table per language.

The place words of an instruction are whatever the learned vocabulary holds (on-site names, any language); this
module only lists the closed-class words that say what role a named place plays and in which order places are
visited:

* ``goal``: where the robot must end ("to", "into", "return to", "on the way to"; へ, に行って, に戻って).
* ``waypoint``: a place to pass on the way ("via", "through", "pass", "stop at", "swing by"; を通って, に寄って).
* ``avoid``: a place the path must not enter ("avoiding", "without passing", "not through", and negations of going
  there: "don't go to", "never pass"; を避けて, を通らずに, に行かないで, は通らないで). A negation followed by
  other markers with only fillers between ("I don't want to go to the kitchen") keeps the avoid role.
* ``not_goal``: a place that must not be the goal but may be passed ("instead of", "rather than"; ではなく,
  の代わりに). "Go to the bedroom instead of the kitchen" corrects the destination; nothing in it forbids
  driving through the kitchen, so the kitchen is not avoided, only never chosen as the goal.
* ``from``: the place the robot starts in ("from"; から). The start is the pose given to the planner, so such a
  phrase is parsed and then ignored.

``order`` words say when a place is visited (:mod:`spcotmhp.planning.sequence` applies them):
``first`` ("first", まず), ``last`` ("finally", 最後に), ``before`` ("before the bedroom, visit the toilet";
寝室に行く前に), ``after`` ("go to the bedroom after the kitchen"; キッチンの後で), ``before_that`` ("but before
that the kitchen"; その前に) and ``on_the_way`` ("on the way", 途中で: the place is a waypoint, not the goal).
``sequencers`` ("then", "after that"; それから) are connectors that also start a new step when a new marker follows.

Three kinds of phrases are recognised only to be refused (the parser raises
:class:`~spcotmhp.errors.UnsupportedPhrase` naming them rather than guessing): ``alternatives`` ("or", "either";
または) leave the choice of a place open, ``relations`` ("next to", "near"; の隣) describe a place by a spatial
relation to another, and ``modifiers`` ("second", "on the left", "big"; 二番目, 左の) pick one of several places
by a property the map does not hold. "the first" / "the last" before a place are modifiers too.

``attach`` says on which side of its place phrase a marker stands: English markers are prepositions (``prefix``:
"via the corridor"), Japanese ones are postpositions (``postfix``: 廊下を通って). ``connectors`` ("and", "then", と)
let the next phrase share a role ("avoiding the living and the kitchen"; トイレとダイニングを経由して).
English is matched on lower-cased word tokens, Japanese on characters (no spaces needed); the longest table
entry wins, and a place word wins over a grammar word of the same length.
"""

from __future__ import annotations

from dataclasses import dataclass, field

ROLES = ("goal", "waypoint", "avoid", "not_goal", "from")
ORDERS = ("first", "last", "before", "after", "before_that", "on_the_way")


@dataclass(frozen=True)
class Grammar:
    """The grammar words of one language.

    Attributes:
        lang: language code ("en", "ja").
        attach: "prefix" (marker before its place phrase) or "postfix" (marker after it). Order words follow
            the same side, except ``backward_order`` ones (Japanese 前に, 後で stand after their place).
        markers: phrase -> role, phrases as written (English: space-separated words).
        connectors: phrases that continue the previous role.
        sequencers: the connectors that put what follows after what precedes ("then"; module docstring).
        order: phrase -> one of :data:`ORDERS`.
        backward_order: order kinds whose phrase stands after the place it orders (Japanese before/after).
        soft_connectors: the connectors that are only punctuation (",", 、) or "but": unknown words after them
            are reported only when they follow a determiner ("go to the kitchen, thanks" is fine, "go to the
            kitchen, the attic" is not).
        determiners: fillers that open a noun phrase ("the", "my"); "the first" / "the last" are modifiers.
        alternatives: phrases offering a choice between places ("or"), refused.
        relations: spatial relations between places ("next to"), refused.
        modifiers: words that pick one of several places by order, side or size ("second", "left"), refused.
        between_places: short words that mean something only when they stand alone between two place
            phrases (Japanese: の joins them into one name, 玄関の廊下; か offers alternatives, キッチンかトイレ):
            word -> "join" or "alternative". Elsewhere they are ordinary characters of other words.
        fillers: words and phrases that carry no meaning for the parse (politeness, verbs of motion, "wait").
            Never reported as "not understood"; never place words unless a place is named so.
        nouns: generic nouns among the fillers ("room", "area"): skipped after a place word ("the living room")
            but, unlike the other fillers, allowed as words of a place's name ("alice's room").
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
    sequencers: frozenset[str] = frozenset()
    order: dict[str, str] = field(default_factory=dict)
    backward_order: frozenset[str] = frozenset()
    modifiers: frozenset[str] = frozenset()
    nouns: frozenset[str] = frozenset()

    @property
    def function_words(self) -> frozenset[str]:
        """Every grammar and filler word (never a place word), generic nouns excepted."""
        return ((self.fillers - self.nouns) | self.connectors | set(self.markers) | set(self.order)
                | self.determiners | self.alternatives)


def _roles(**groups: tuple[str, ...]) -> dict[str, str]:
    return {phrase: role for role, phrases in groups.items() for phrase in phrases}


ENGLISH = Grammar(
    lang="en",
    attach="prefix",
    markers=_roles(
        goal=("to", "into", "toward", "towards", "reach", "until", "at", "return to", "back to", "come back to",
              "on the way to", "on your way to", "on its way to", "end at", "end up in", "end up at", "finish at",
              "finish in", "over to", "up to", "down to", "inside", "as far as"),
        waypoint=("via", "through", "thru", "passing", "passing by", "passing through", "pass by", "pass through",
                  "pass", "go through", "going through", "by way of", "past", "go past", "going past",
                  "stopping at", "stop at", "stop by", "stopping by", "stop off at", "stop in at", "swing by",
                  "swinging by", "drop by", "dropping by", "drop in at", "pop by", "pop into", "call at", "visiting",
                  "cross", "crossing", "go by", "going by"),
        avoid=("avoid", "avoiding", "avoids", "not", "not through", "not via", "not passing", "not passing by",
               "not passing through", "without", "without passing", "without passing by", "without passing through",
               "without going through", "without entering", "don't go through", "do not go through",
               "don't pass", "don't pass through", "do not pass", "do not pass through", "don't enter",
               "do not enter", "except", "but not", "bypass", "bypassing", "skip", "skipping", "stay out of",
               "keep out of", "away from", "don't", "dont", "do not", "never", "don't go to", "do not go to",
               "don't go into", "do not go into", "never go to", "never go into", "never go through", "never pass",
               "never pass by", "never pass through", "never enter", "never visit", "don't visit", "do not visit",
               "not to", "not into", "without going to", "without visiting", "steer clear of",
               "stay clear of", "keep clear of", "no going through", "don't cross", "do not cross", "without crossing",
               "don't go past", "do not go past", "don't use", "do not use"),
        not_goal=("instead of", "rather than", "not the"),
        **{"from": ("from", "starting from", "leaving", "starting at", "starting in")},
    ),
    connectors=frozenset({"and", "then", "and then", "after that", "afterwards", "next", "and next", "after which",
                          ",", ";", "&", "but", "plus", "and also"}),
    sequencers=frozenset({"then", "and then", "after that", "afterwards", "next", "and next", "after which"}),
    order={**dict.fromkeys(("first", "first of all", "to begin with", "to start with", "before anything else",
                            "at first", "firstly"), "first"),
           **dict.fromkeys(("finally", "lastly", "last", "last of all", "in the end", "at the end", "eventually"),
                           "last"),
           **dict.fromkeys(("before", "prior to", "ahead of"), "before"),
           **dict.fromkeys(("after",), "after"),
           **dict.fromkeys(("before that", "before this", "but before that", "prior to that", "before doing that",
                            "before you do that", "before you do"), "before_that"),
           **dict.fromkeys(("on the way", "on your way", "along the way", "en route", "on the way there",
                            "on your way there", "while you are at it", "while you're at it", "as you go"),
                           "on_the_way")},
    soft_connectors=frozenset({",", ";", "but"}),
    determiners=frozenset({"the", "a", "an", "my", "our", "your", "this", "that", "his", "her", "their"}),
    alternatives=frozenset({"or", "either", "or else", "whichever", "any of", "one of"}),
    relations=frozenset({"next to", "near", "near to", "nearby", "close to", "beside", "behind", "in front of",
                         "opposite", "opposite to", "across from", "between", "left of", "right of", "above",
                         "below", "beyond", "adjacent to", "around the corner from", "facing"}),
    modifiers=frozenset({"second", "third", "fourth", "fifth", "2nd", "3rd", "4th", "5th", "other", "another",
                         "left", "right", "leftmost", "rightmost", "on the left", "on the right", "to the left",
                         "to the right", "on your left", "on your right", "upstairs", "downstairs", "big", "bigger",
                         "biggest", "small", "smaller", "smallest", "large", "larger", "largest", "little", "main",
                         "master", "guest", "spare", "farthest", "furthest", "far", "upper", "lower", "top",
                         "bottom", "middle", "front", "rear", "old", "new", "same", "kids"}),
    fillers=frozenset({"the", "a", "an", "my", "our", "your", "this", "that", "his", "her", "their", "please",
                       "go", "goes", "going", "take", "me", "us", "bring", "get", "head", "heading", "move",
                       "navigate", "drive", "walk", "come", "lead", "guide", "can", "could", "would", "will",
                       "you", "i", "we", "it", "want", "need", "needs", "let's", "let", "room", "place", "area",
                       "way", "there", "here", "now", "robot", "hey", "hi", "hello", "ok", "okay", "again",
                       "back", "along", "of", "all", "by", "on", "in", "side", "enter", "visit", "is", "are", "am",
                       "be", "called", "name", "named", "this's", "um", "uh", "er", "erm", "so", "well", "look",
                       "once", "quickly", "slowly", "carefully", "thanks", "thank", "immediately", "soon",
                       "right away", "right now", "straight", "i'd", "i'm", "you're", "we're", "it's", "like",
                       "mind", "may", "might", "should", "must", "have", "has", "had", "just", "kindly", "also",
                       "too", "as well", "if", "possible", "wait", "stay", "stop", "remain", "for", "there's",
                       "return", "returning", "over", "up", "down", "make", "your way", "way to", "trip",
                       "run", "hurry", "pop", "nearest", "closest", "nearby one", "do", "did", "does",
                       "help", "would like", "love", "sure", "alright", "buddy", "could you please",
                       "when", "done", "finished", "with", "while", "instead", "lot", "as quickly as possible", "all right", "that's right", "asap", "quick", "thx", "pls", "plz", }),
    nouns=frozenset({"room", "place", "area", "side"}),
)

JAPANESE = Grammar(
    lang="ja",
    attach="postfix",
    markers=_roles(
        goal=("へ", "に", "まで", "へ行って", "に行って", "まで行って", "へいって", "にいって", "までいって",
              "へ行く", "に行く", "へいく", "にいく", "に連れて行って", "につれていって", "へ連れて行って",
              "へつれていって", "に連れてって", "につれてって", "に向かって", "へ向かって", "にむかって", "へむかって",
              "に移動して", "へ移動して", "行って", "いって", "に戻って", "へ戻って", "にもどって", "へもどって",
              "まで戻って", "に帰って", "へ帰って", "にかえって", "に行き", "へ行き", "に行った", "へ行った",
              "に行ってきて", "へ行ってきて", "に戻る", "へ戻る", "に着いたら", "に向かう", "へ向かう", "で待って",
              "で待ってて", "でまってて", "で待機して", "で止まって"),
        waypoint=("を通って", "をとおって", "通って", "とおって", "を経由して", "経由して", "をけいゆして", "けいゆして",
                  "経由で", "けいゆで", "を通り", "をとおり", "を通過して", "に寄って", "によって", "へ寄って",
                  "を回って", "をまわって", "に立ち寄って", "にたちよって", "を抜けて", "をぬけて", "を通った",
                  "に寄った", "を通る", "に寄る", "を経由", "経由", "寄って", "に寄り", "を通ってから",
                  "に寄ってから", "を横切って", "を通過"),
        avoid=("を避けて", "をさけて", "避けて", "さけて", "を通らずに", "をとおらずに", "を通らないで", "をとおらないで",
               "を通らず", "をとおらず", "を経由せずに", "をけいゆせずに", "に入らずに", "にはいらずに", "に入らないで",
               "にはいらないで", "に寄らずに", "によらずに", "以外", "いがい", "を除いて", "をのぞいて",
               "に行かないで", "へ行かないで", "には行かないで", "へは行かないで", "に行かずに", "へ行かずに",
               "にいかないで", "へいかないで", "にはいかないで", "にいかずに", "行かないで", "いかないで",
               "入らないで", "はいらないで", "には入らないで", "には入らずに", "は通らないで", "はとおらないで",
               "は通らずに", "はとおらずに", "を通らないでください", "は避けて", "はさけて", "に寄らないで",
               "には寄らないで", "を通らないように", "は通らないように", "には近づかないで", "に近づかないで",
               "を避けながら", "を避けつつ", "は通らず"),
        not_goal=("ではなく", "ではなくて", "じゃなく", "じゃなくて", "の代わりに", "のかわりに", "ではなしに"),
        **{"from": ("から",)},
    ),
    connectors=frozenset({"と", "、", ",", "，", "それから", "そして", "その後", "そのあと", "や", "次に", "つぎに",
                          "その次に", "その後で", "そのあとで", "けど", "けど、"}),
    sequencers=frozenset({"それから", "そして", "その後", "そのあと", "次に", "つぎに", "その次に", "その後で",
                          "そのあとで"}),
    order={**dict.fromkeys(("まず", "まずは", "最初に", "さいしょに", "はじめに", "初めに", "先に", "さきに"), "first"),
           **dict.fromkeys(("最後に", "さいごに", "最終的に"), "last"),
           **dict.fromkeys(("前に", "まえに", "の前に", "のまえに"), "before"),
           **dict.fromkeys(("後で", "あとで", "後に", "あとに", "の後で", "のあとで", "の後に", "のあとに"), "after"),
           **dict.fromkeys(("その前に", "そのまえに"), "before_that"),
           **dict.fromkeys(("途中で", "とちゅうで", "途中に", "とちゅうに", "ついでに"), "on_the_way")},
    backward_order=frozenset({"before", "after"}),
    soft_connectors=frozenset({"、", ",", "，", "けど", "けど、"}),
    alternatives=frozenset({"または", "もしくは", "あるいは", "それとも", "どちらか", "どっちか"}),
    between_places={"の": "join", "か": "alternative"},
    relations=frozenset({"の隣", "のとなり", "の近く", "のちかく", "の横", "のよこ", "の前", "のまえ", "の後ろ",
                         "のうしろ", "の向かい", "のむかい", "のそば", "の奥", "のおく", "の間", "のあいだ"}),
    modifiers=frozenset({"一番目", "二番目", "三番目", "1番目", "2番目", "3番目", "１番目", "２番目", "３番目",
                         "左の", "右の", "左側", "右側", "ひだりの", "みぎの", "大きい", "小さい", "おおきい", "ちいさい",
                         "大きな", "小さな", "別の", "もう一つの", "もうひとつの", "二階の", "2階の", "１階の", "1階の",
                         "上の", "下の", "奥の", "手前の", "一番奥", "一番遠い"}),
    fillers=frozenset({"ここ", "ここが", "ここは", "ここわ", "こちら", "こちらが", "この", "ここの", "です", "だよ",
                       "になります", "にきました", "ください", "ロボット", "このばしょ", "このばしょが",
                       "このばしょは", "このばしょわ", "このばしょの", "このばしょのなまえは", "このばしょのなまえわ",
                       "ここのなまえは", "ここのなまえわ", "なまえ", "わこちらです", "はこちらです", "ねえ", "えっと",
                       "あの", "じゃあ", "では", "ちょっと", "すみません", "すいません", "お願い", "おねがい",
                       "お願いします", "おねがいします", "早く", "はやく", "すぐ", "すぐに", "ゆっくり", "一番近い",
                       "いちばん近い", "近くの", "待って", "待ってて", "まってて", "待っていて", "待機して", "止まって",
                       "もらえますか", "くれますか", "くれる", "ほしい", "欲しい", "ね", "よ", "。", "！", "？", "!",
                       "?", "ロボットさん", "もう一度", "もういちど", "また", "今から", "いまから", "急いで", "そこで",
                       "そこ", "の方", "のほう", "でも", "行ってきて", "ください。"}),
    by_character=True,
)

GRAMMARS: dict[str, Grammar] = {"en": ENGLISH, "ja": JAPANESE}
"""The grammar of each supported language; add a language by adding a table here."""
