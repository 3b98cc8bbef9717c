"""Japanese as people say it, before the grammar reads it (issue 34): the endings of a verb that carry no navigation
meaning, said in their plain form, and talk around the instruction passed over.

* **Verb endings** (:func:`plain_verbs`): a verb of the table's ``verbs`` (行く, 来る, 向かう, 入る, 通る, 寄る, 待つ,
  止まる, 移動, 待機; お願い and 頼む) followed by auxiliaries, auxiliary verbs and sentence-final particles, as the
  morphological analyser janome tags them (the part-of-speech tags that come with the segmenter), is written in
  its plain te-form (行っとくれ, 行ったってや, 行っといでや, 行けたりする, 行きなさい -> 行って; 待機しといて ->
  待機して; 頼めるかな -> お願い): aspect, mood, politeness and requests (〜ておく, 〜てくれ, 〜てる, 〜たって,
  〜なさい, か, な, わ) change nothing of where the robot goes. A negation among the endings (ない, ん, ず) gives the
  negative te-form (入らんといて -> 入らないで); a condition (ば, たら, なら) or a waiver (寄らなくていい, 通らなくても)
  leaves the verb as said, for the grammar to read or refuse. A long vowel mark after hiragana is a drawn-out
  sound (しまーす, 行ってー), left out, but for a filler's (えー).
* **Talk** (:func:`pass_over_ja`): a run of words with no place, length of time, floor or word class but a
  reason's から / ので, each of its words one janome knows, no number and none of the table's ``talk.meaning``,
  ending with から / ので or at a sentence's end, and holding a verb or an adjective, is passed over
  (宅配来るっぽいから, 床が濡れているので, もうすぐご飯だよ), with the place it is said of when that place opens the
  clause and is said again after it (お風呂沸いたよ、風呂場に行って, 玄関にお客さん来るから玄関まで:
  :func:`_subject`); a run that ends as a request (a te-form, an imperative, くれる, ください, ほしい: テレビを
  つけて, コップ持ってきて) asks for an action and stays, to be refused.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Sequence
from typing import Any

from spcotmhp.language.placewords import Token
from spcotmhp.language.table import WordTable

_ELONGATION = re.compile(
    r"(?<=[\u3041-\u30fb\u4e00-\u9fff][\u3041-\u309f])(?:ー+|[〜～~]+(?=(?![おご][\u30a0-\u30ff\u4e00-\u9fff])[\u3041-\u309f]|[、。,.!?！？\s]|$))"
)
"""A drawn-out sound inside a word (しまーす, 行ってー); not after a word's first kana (えー, あー: fillers); a wave
dash before a word in katakana or kanji, or one with an honorific お / ご, stays (できたよ〜ダイニング, 沸いたよ〜
お風呂場: there it is a pause, read as 、)."""
_TAIL_PARTICLES = ("接続助詞", "終助詞", "副助詞／並立助詞／終助詞", "並立助詞", "副助詞", "副詞化")
_NEGATION = frozenset({"ない", "ん", "ぬ", "ず", "まい"})
_CONDITION = frozenset({"ば", "たら", "なら", "ならば"})
_CLAUSE_ENDS = frozenset({"から", "ので", "けど", "けれど", "が", "し"})
_REQUESTS = frozenset({"お願い", "願う", "頼む", "頼める"})
_BEING = frozenset({"いる", "おる"})
_CONJECTURE = frozenset({"です", "だ", "らしい", "っぽい", "みたい", "そう"})
_ASKING = frozenset({"くれる", "くださる", "下さる", "もらえる", "いただける", "頂ける"})
"""Verbs asking a favour after a te-form: a negation after one makes a question (くれない？ will you?), while one
before it negates the verb (行かないでくれる); ほしくない and the like stay negations."""


def plain_verbs(text: str, table: WordTable) -> str:
    """``text`` (normalised) with each verb of the table's ``verbs`` and its endings in the plain form (module
    docstring)."""
    verbs: dict[str, list[str]] = dict(table.talk.get("verbs", {}))
    if not verbs:
        return text
    text = _ELONGATION.sub("", text)
    for said, standard in _dialect(table):
        text = said.sub(standard, text)
    text = relayed(text)
    morphemes = _analyse(text)
    out: list[str] = []
    i = 0
    while i < len(morphemes):
        surface, pos, sub, base = morphemes[i]
        key = base if base in verbs else surface if surface in verbs else None
        if key is None and base == "いう" and i > 0 and (morphemes[i - 1][0] in ("まで", "へ", "に") or
                                                          morphemes[i - 1][1] == "名詞"):  # fmt: skip
            key = "いく"  # ろうかまでいってみて, げんかんいっといて: 言う takes と or を; after a place it is 行く
        if key is None or pos not in ("動詞", "名詞"):
            out.append(surface)
            i += 1
            continue
        start = i + 1
        if pos == "名詞" and start + 1 < len(morphemes) and morphemes[start][0] == "を":  # 移動をお願い
            start += 1 if morphemes[start + 1][3] in _REQUESTS else 0
        j, negative, condition = _tail(morphemes, start)
        following = morphemes[j] if j < len(morphemes) else None
        kept = (
            j == i + 1
            and key not in _REQUESTS
            and (following is None or following[1] == "名詞" or surface == verbs[key][0])
        )
        if key in _BEING and (i == 0 or morphemes[i - 1][0] != "に"):
            kept = True  # 赤ちゃんおるけえ: someone is somewhere; only "Xにいて" asks the robot to be at X
        if i > 0 and morphemes[i - 1][0] == "が" or _reported(morphemes, i + 1, j):
            kept = True  # 救急隊が来るから, 誰か来た: what someone else does or did, no request
        if kept and j == i + 1 and following is None and _imperative(surface):
            kept = False  # 来い, 行け: the imperative asks for the motion, as the te-form does
        if condition or kept or negative and len(verbs[key]) < 2:  # 行ったら, 行く前に, 待たないで: as said
            out.append("".join(m[0] for m in morphemes[i:j]))
        else:
            if out and i > 0 and morphemes[i - 1][1] == "接頭詞" and pos == "動詞":
                out.pop()  # お行きなさい: the honorific お of the verb goes with its ending
            out.append(verbs[key][1 if negative else 0])
        i = j
    return "".join(out)


@functools.cache
def _dialect_of(items: tuple[tuple[str, str], ...]) -> tuple[tuple[re.Pattern, str], ...]:
    return tuple((re.compile(said), standard) for said, standard in items)


def _dialect(table: WordTable) -> tuple[tuple[re.Pattern, str], ...]:
    """The table's regional endings (``talk.dialect``), compiled once."""
    return _dialect_of(tuple(dict(table.talk.get("dialect", {})).items()))


def _reported(morphemes: Sequence[tuple[str, str, str, str]], start: int, j: int) -> bool:
    """Whether a verb's endings ``morphemes[start:j]`` end a statement: the past た last (来た), a conjecture
    or hearsay among them (来るでしょう, 来るっぽい, 来るらしい, 来るそう), or a reason's
    から / ので after them that follows no te-form (来るから, 来るっぽいから; 行ってから says "after")."""
    said = [m for m in morphemes[start:j] if not (m[1] == "助詞" and m[2] == "終助詞")]
    guessed = any(
        m[3] in _CONJECTURE and (m[1] != "助動詞" or k + 1 < len(said) and said[k + 1][3] == "う")
        for k, m in enumerate(said)
    )  # 来るでしょう, 来るだろう (です / だ before う), 来るっぽい; 行くんだが is said as going
    if guessed and any(m[3] in _REQUESTS or m[3] in _ASKING or m[3] == "できる" for m in said):
        guessed = False  # 移動お願いできますでしょうか: a request asked politely, not a guess about it
    if said and said[-1][1] == "助動詞" and said[-1][3] == "た" or guessed:
        return True
    te = bool(said) and said[-1][0] in ("て", "で") and said[-1][1] == "助詞"
    return not te and j < len(morphemes) and morphemes[j][0] in ("から", "ので")


def _tail(morphemes: Sequence[tuple[str, str, str, str]], j: int) -> tuple[int, bool, bool]:
    """Where the endings after a verb stop, and whether they hold a negation or a condition."""
    negative = condition = asked = False
    start = j
    while j < len(morphemes):
        surface, pos, sub, base = morphemes[j]
        asked |= base in _ASKING  # 行ってくれん(ね), 行ってもらえない？: a negative question asks, negating nothing
        if surface in _CLAUSE_ENDS and pos == "助詞" or pos in ("記号",) and surface not in ("ー",):
            break
        if surface in _CONDITION or base in _CONDITION or surface == "ら" and j > 0 and morphemes[j - 1][0] == "た":
            condition = True
        if surface == "も" and j > start and morphemes[j - 1][0] in ("て", "で"):
            condition = True  # 通ってもいい (may pass), 行っても (even if): a permission or a concession, as said
        if surface in ("たり", "だり"):
            condition = True  # 行ったり来たり (back and forth), 寄ったり: a listing of doings, left as said (refused)
        if negative and (surface in ("も", "いい", "よい", "良い") or base in ("いい", "よい", "良い", "大丈夫")):
            condition = True  # 寄らなくていい, 通らなくても: what need not be done, left as said (refused)
        if pos == "助詞" and surface == "な" and j == start and sub == "終助詞":
            negative = True  # 入るな: the dictionary form and な forbid it
        if surface == "に" and pos == "助詞" and j > start and morphemes[j - 1][0] == "ず":
            j += 1  # 通らずに: ずに is the negative te-form, its に no place's marker
            continue
        if pos == "助動詞":
            negative |= not asked and (base in _NEGATION or surface in _NEGATION)
        elif (
            pos == "助詞"
            and (sub in _TAIL_PARTICLES or sub == "格助詞" and surface == "と" and _aux_after(morphemes, j))
            or pos == "動詞"
            and (sub in ("非自立", "接尾") or base in _AUX_VERBS)
            or base in _REQUESTS
        ):
            pass
        elif pos == "形容詞" and (sub in ("非自立", "接尾") or base in ("いい", "良い", "ほしい", "欲しい", "ない")):
            negative |= base == "ない" and not asked
        elif pos == "名詞" and sub == "非自立" and surface in ("ん", "の", "とき", "よう"):
            pass
        elif surface == "も" and pos == "助詞" and j + 1 < len(morphemes) and morphemes[j + 1][3] in _ACCEPTED:
            pass  # 行ってもらってもいい？: asking leave is asking (after a negation it is a waiver, above)
        else:
            break
        j += 1
    return j, negative, condition


_AUX_VERBS = frozenset(
    [  # auxiliary verbs after a te-form
        "くれる",
        "くれ",
        "くださる",
        "下さる",
        "もらう",
        "もらえる",
        "いただく",
        "いただける",
        "頂く",
        "いる",
        "おく",
        "とく",
        "とる",
        "みる",
        "しまう",
        "あげる",
        "やる",
        "なさる",
        "する",
        "できる",
        "いたす",
        "来る",
        "くる",
        "いく",
        "行く",
        "ちょうだい",
    ]
)


def _aux_after(morphemes: Sequence[tuple[str, str, str, str]], j: int) -> bool:
    """と in 入らんといて, 行っとくれ: the contraction of て + おく / いる, followed by an auxiliary verb."""
    return j + 1 < len(morphemes) and morphemes[j + 1][3] in ("いる", "くれる", "おく", "く")


@functools.lru_cache(maxsize=2048)
def _analyse(text: str) -> list[tuple[str, str, str, str]]:
    from spcotmhp.language.text import _tokenizer

    return [
        (m.surface, *_pos(m), m.base_form if m.base_form != "*" else m.surface) for m in _tokenizer().tokenize(text)
    ]


def _pos(m: Any) -> tuple[str, str]:
    """janome's part of speech and its first subclass; ASCII punctuation (what NFKC makes of ？ and ！), which
    janome's dictionary tags as a noun, as the symbol it is."""
    if not m.surface.strip("?!.,"):
        return "記号", "一般"
    pos = m.part_of_speech.split(",")
    return pos[0], pos[1]


def pass_over_ja(toks: Sequence[Token], table: WordTable, text: str = "") -> tuple[list[Token], list[str]] | None:
    """``toks`` without the talk in them, and the talk as said; None when there is none (module docstring).
    ``text``: the sentence (normalised) whose characters, spaces left out, the tokens index: a run is judged with
    the fillers said inside and after it (ぐずぐずするな: the な that forbids)."""
    chars = [ch for ch in text if not ch.isspace()]
    meaning = frozenset(table.talk.get("meaning", ()))
    verbs = frozenset(table.talk.get("verbs", {}))
    cut: set[int] = set()
    said: list[str] = []
    i = 0
    while i < len(toks):
        if toks[i].kind != "WORD":
            i += 1
            continue
        j = i
        while j < len(toks) and (toks[j].kind in ("WORD", "NOW") or toks[j].kind in ("FROM", "DE") and j > i):
            if toks[j].kind in ("FROM", "DE") and not _inner(toks, j):
                j += 1
                break
            j += 1
            while j < len(toks) and _inner(toks, j):
                j += 1  # お茶にするから, もうご飯やから: a particle between two words of a clause with no place
        ends = toks[j - 1].kind in ("FROM", "DE") or j == len(toks) or toks[j].kind in ("_STOP", "COMMA")
        before = (
            toks[i - 1] if i > 0 else None
        )  # after a verb, not after a bare particle (玄関に荷物が届いて: the place's)
        starts = before is None or before.kind in ("_STOP", "COMMA", "GO", "WAIT") or (
            before.kind == "GOAL" and before.surface not in ("に", "へ", "まで"))  # fmt: skip
        subject = 0 if starts else _subject(toks, i, j)  # お風呂沸いたよ、風呂場に行って
        run = toks[i:j]
        said_as = "".join(chars[run[0].start : toks[j].start if j < len(toks) else len(chars)]) if chars else ""
        ends = ends or said_as.endswith(_FINAL)  # お客さん来たよ玄関行って: a sentence-final particle is a pause
        if ends and (starts or subject) and _reason(run, meaning, said_as, verbs):
            cut.update(range(i - subject, j))
            said.append("".join(t.surface for t in toks[i - subject : j]))
        i = j
    return without(toks, cut, said)


def _subject(toks: Sequence[Token], i: int, j: int) -> int:
    """How many tokens before the run ``toks[i:j]`` (a place, and a bare に / で after it) belong to its statement:
    the place opens the clause and is said again after it. "X + a verb said of it" (お風呂沸いたよ: the bath is
    ready, が left out; 玄関にお客さん来るから: a guest comes to the entrance) is a statement about X, and X said
    again after it carries the instruction, so passing the statement over loses no place. 0: none."""
    marked = i > 1 and toks[i - 1].kind in ("GOAL", "DE") and toks[i - 1].surface in ("に", "で")
    k = i - 1 - marked
    x = toks[k] if k >= 0 else None
    if x is None or x.kind != "PLACE" or k > 0 and toks[k - 1].kind not in ("_STOP", "COMMA"):
        return 0
    return i - k if any(t.kind == "PLACE" and t.words == x.words for t in toks[j:]) else 0


def _inner(toks: Sequence[Token], j: int) -> bool:
    """Whether ``toks[j]`` is a bare particle between two words (に, へ, で, と, や) or a word and the reason's から
    (ご飯やから: や the copula), marking no place: with no place in the clause it carries no navigation meaning."""
    bare = toks[j].kind in ("AND", "DE") or toks[j].kind == "GOAL" and toks[j].surface in ("に", "へ")
    return bare and j + 1 < len(toks) and toks[j + 1].kind in ("WORD", "FROM") and toks[j - 1].kind == "WORD"


def without(toks: Sequence[Token], cut: set[int], said: list[str]) -> tuple[list[Token], list[str]] | None:
    """The tokens but those at ``cut`` (talk), with the talk as said; None when nothing is cut or no place is
    left to go to (the sentence was talk only: it is refused as it stands)."""
    if not cut:
        return None
    kept = [t for k, t in enumerate(toks) if k not in cut]
    if not any(t.kind == "PLACE" for t in kept):
        return None
    return kept, said


def _reason(
    run: Sequence[Token], meaning: frozenset[str], said_as: str = "", verbs: frozenset[str] = frozenset()
) -> bool:
    """Whether a run of words is talk: every word known to janome, no number, none of ``meaning`` but the
    statement's own (:func:`_own`), and a verb or an adjective among them (a statement, not a name); ``said_as``:
    the run with its fillers, as said; ``verbs``: the table's verbs of going, waiting and asking."""
    text = said_as or "".join(t.surface for t in run)
    if not any(t.kind == "WORD" for t in run):
        return False
    if run[-1].kind == "DE" and not text.endswith("ので"):
        return False  # で after a word: a place's marker (洗面台で), not "because"
    morphemes = _known(text)
    if morphemes is None:
        return False
    theirs = _someone_moves(morphemes) | _own(morphemes, verbs)
    if any(m[1] == "名詞" and m[2] == "数" or _means(m, meaning) and k not in theirs for k, m in enumerate(morphemes)):
        return False
    if any(m[3] in _REQUESTING for m in morphemes) or _ordered(morphemes):
        return False  # テレビをつけて, コップ持ってきて: a request (an action), not a statement
    if any(m[3] in _ACCEPTED and k > 0 and morphemes[k - 1][0] in ("で", "も") for k, m in enumerate(morphemes)):
        return False  # のんびりでいいから, どこでもいい: what way of doing it will do, a part of the instruction
    return any(
        m[1] in ("動詞", "形容詞") or m[1] == "助動詞" and m[3] in ("だ", "です", "や", "じゃ") for m in morphemes
    )


_FINAL = ("よ", "ね", "わ", "ぞ", "よね", "よー", "ねー")
"""Sentence-final particles: a clause ending in one is a sentence, though no mark of a pause follows it."""
_THEIR_MOTIONS = frozenset({"帰る", "戻る", "来る", "出る"})
_REQUESTED = r"(?:(?<=[てでけろ])|(?<=なさい)|(?<=ください))"
_SAY_ENDS = (
    r"(?:っ(?:て(?:る|た|いる|いた|ます|ました)?|た|とる|とった)|う|います|いました)(?:んだ|の|よ|でしょ|だろ|ぞ|ね)*"
)
"""The saying said as done or being done, affirmative (言ってた, 言っとるんだ, 言うたよ): never 言ってない, 言わないで,
言うな, 言いたかった, 言いかけた, 言っといて (tell them), 言われた (was told), which stay as said."""
_SAID = re.compile(_REQUESTED + r"\s*(?:って|と)\s*(?:言|い)" + _SAY_ENDS + r"(?=[。！!、,\s]|$)")
_SAID_BUT = re.compile(
    _REQUESTED
    + r"\s*(?:って|と)\s*(?:言|い)(?:った|ってた|ってたん|われた|われてた)(?:だ)?(?:けど|けれど|が)(?=[、,\s])"
)
_KIN_ENDINGS = "さん|ちゃん|くん|様|パパ|ママ|じい|ばあ|父|母|兄|姉|弟|妹"
"""Endings of a word naming a person (ちゃん, 母): one list for the sayer of a request and someone who moves."""
_SAYER = re.compile(r"^\s*([^、。,\s]{1,12}?)が(?:ね|さ|な)?(?:[、,\s]|(?=[^、。,\s]))")
_KIN = re.compile(rf"(?:{_KIN_ENDINGS}|ぱぱ|まま|先生)$")


def relayed(text: str) -> str:
    """A request said with the words that say it was said (風呂へ行けと言っとるんだ: "I'm telling you, go to the
    bath"; おばあちゃんがね、風呂場に行ってって言ってたよ: granny said go to the bathroom) is that request: the
    saying is left out, and with it the person who said it, a kin word or a name with さん / ちゃん before が
    opening the sentence; "X って言ったけど、" (I said X, but; was told X, but) is a correction of X
    (キッチン通ってって言ったけど、ダイニング通って...). A quote of anything but a request (te-form, imperative),
    and a saying denied, forbidden, wished or asked for (言ってない, 言うな, 言いたかった, 言っといて), stay as said."""
    said = _SAID_BUT.sub("、いや", text)  # "I said X, but": a correction of X
    quoted = _SAID.sub("", said)
    if quoted != said:
        sayer = _SAYER.match(quoted)
        if sayer and _KIN.search(sayer.group(1)):
            quoted = quoted[sayer.end() :]
    return quoted


PEOPLE = re.compile(rf"(?:{_KIN_ENDINGS}|客|人)$")
"""A word naming a person: before 帰る / 来る the person comes or goes home, not the robot (rewrite_ja too)."""


def _someone_moves(morphemes: Sequence[tuple[str, str, str, str]]) -> set[int]:
    """The motion verbs said of someone else (パパが帰ってくる, じいちゃん帰ってきた, お客さん来た): a noun with が, or
    a word for a person, right before the verb; their motion is theirs, not an instruction to the robot."""
    out: set[int] = set()
    for k, m in enumerate(morphemes):
        if m[1] != "動詞" or m[3] not in _THEIR_MOTIONS or k == 0:
            continue
        before = morphemes[k - 1]
        marked = before[0] == "が" and k > 1 and morphemes[k - 2][1] == "名詞"
        if marked or before[1] == "名詞" and PEOPLE.search(before[0]):
            out.add(k)
    return out


_OWN = frozenset(
    {"今", "今日", "きょう", "明日", "あした", "今夜", "夜", "朝", "昼", "夕方", "もう", "あと", "後", "あとで", "後で",
     "ない", "ず", "ぬ", "ん", "静か"}
)  # fmt: skip


def _own(morphemes: Sequence[tuple[str, str, str, str]], verbs: frozenset[str]) -> set[int]:
    """The words of time, negation and quiet a statement holds of itself, when none of its verbs is one of
    going, waiting or asking (``verbs``): 今会議中だから (the meeting is now), 手が離せない (the speaker
    cannot), あとで呼ぶけん (the speaker calls later), 静かにね (six writers mark a slow trip with ゆっくり,
    never with 静か alone); 中 after a noun (会議中, テレビ中: during) is no place, and 時間 after の
    (歯磨きの時間だから: time for) no length. With a verb of the table (今行くから, 入らないから) they may be
    the robot's, and keep the run."""
    if any(m[1] == "動詞" and (m[3] in verbs or m[3] == "言う") for m in morphemes):
        return set()  # 言う may carry a quoted request (行けなんて言ってない): its negation is no statement's own
    return {
        k for k, m in enumerate(morphemes)
        if m[0] in _OWN or m[3] in _OWN or m[0] == "中" and m[2] == "接尾"
        or m[0] == "時間" and k > 0 and morphemes[k - 1][0] == "の"
    }  # fmt: skip


def _means(m: tuple[str, str, str, str], meaning: frozenset[str]) -> bool:
    """Whether a morpheme is one of the ``meaning`` words; ん and の that explain (来るんだから: janome's
    dependent noun) are not the negation ん."""
    return (m[0] in meaning or m[3] in meaning) and not (m[1] == "名詞" and m[2] == "非自立" and m[0] == "ん")


_ACCEPTED = frozenset({"いい", "よい", "良い", "結構", "構う", "大丈夫"})
_REQUESTING = frozenset(
    {"くれる", "くださる", "下さる", "もらう", "いただく", "ほしい", "欲しい", "ちょうだい", "なさる"}
)


def _ordered(morphemes: Sequence[tuple[str, str, str, str]]) -> bool:
    """Whether the words end as a request: a te-form (つけて, 持ってきて) or an imperative."""
    words = [m for m in morphemes if m[1] != "記号" and not (m[1] == "助詞" and m[2] == "終助詞")]
    if not words:
        return False
    last = words[-1]
    prohibits = any(m[0] == "な" and m[1] == "助詞" and m[2] == "終助詞" for m in morphemes[-2:])  # するな
    return last[0] in ("て", "で") and last[1] == "助詞" or _imperative(last[0]) or prohibits


def _imperative(surface: str) -> bool:
    from spcotmhp.language.text import _tokenizer

    m = next(iter(_tokenizer().tokenize(surface)), None)
    return m is not None and getattr(m, "infl_form", "").startswith("命令")


def _known(text: str) -> list[tuple[str, str, str, str]] | None:
    """janome's morphemes of ``text``, or None when one of them is unknown to its dictionary."""
    from spcotmhp.language.text import _tokenizer

    out: list[Any] = []
    for m in _tokenizer().tokenize(text):
        if getattr(m, "node_type", "") == "UNKNOWN" or m.base_form == "*" and m.part_of_speech.startswith("名詞"):
            return None
        out.append((m.surface, *m.part_of_speech.split(",")[:2], m.base_form))
    return out
