"""Japanese sentences -> tokens (rules of :mod:`spcotmhp.language.lexicon`, on characters): the longest match
over the place words (with their spelling variants) and the table's phrases, fillers left out after matching, a
run of unmatched characters one WORD; digits or kanji numerals before 秒, 分 or 時間 a DURATION (1分半: 90 s); a floor
phrase (2階の, 上の階の: :mod:`spcotmhp.language.floors`) a FLOOR; a lone
の between two places joins them into one name (玄関の廊下); か is a choice only between two places.
"""

from __future__ import annotations

import re

from spcotmhp.language.apologies_ja import APOLOGIES, NUMBER_AGAIN, after_a_place, apologies, held, reasons
from spcotmhp.language.floors import floor_ja
from spcotmhp.language.placewords import PlaceLexicon, Token, longest_match
from spcotmhp.language.table import WordTable

_JA_KANA_NUMBER = re.compile(
    r"(?:の)?(?:いち|に|さん|よん|ご)(?:ばん|番)(?!近|遠|大|小|広|狭|ちか|とお|おお|ちい|ひろ|せま|でか|でっか|こま|離|はな)"
)
"""A kana number right after a place (寝室にばん); not いちばん before an adjective (寝室 いちばん ちいさい: "most")."""
_JA_KANA_BEFORE = re.compile(r"(?:いち|さん|よん|ご)(?:ばん|番)の")
_JA_DURATION = re.compile(
    r"(\d+(?:\.\d+)?|[一二三四五六七八九十]+|半(?=時間))(秒|分|時間|びょう|ぷん|ふん|じかん)(半)?(?:間)?"
    r"(?:ほど|くらい|ぐらい|程度|だけ|ばかり)?(?:だけ)?"
)
"""A length of time: 2分, 十五秒, 1分半, 半時間 (half an hour), in kana too (10ぷん, 30びょう: children, learners);
ほど, くらい, 程度, ばかり (about) and だけ (only) say nothing more of its length."""
_JA_LATER = re.compile(r"(?:後|あと|ご(?=に|で|から))(?:に|で|から)?")
"""After a length of time: a delay (10分後に, 5分あとで), which the planner cannot honour."""
_KANJI_DIGITS = {"一": 1, "二": 2, "三": 3, "四": 4, "五": 5, "六": 6, "七": 7, "八": 8, "九": 9}
_FLOOR_STARTS = frozenset("0123456789一二三四五六七八九十地上下ひ")
_JA_UNITS = {"秒": 1, "分": 60, "時間": 3600, "びょう": 1, "ぷん": 60, "ふん": 60, "じかん": 3600}


def _filler_fitting(
    chars: list[str], i: int, table: WordTable, places: PlaceLexicon, hit: tuple[str, str, int] | None
) -> tuple[str, str, int] | None:
    """The longest match, or a shorter entry when the longest filler strands the character after it and the
    shorter one lets a match reach past it (えっと + ねえ, not えっとね + a stray え; で + すみません, not です +
    みません): a filler said next to another word is left out, whichever way their characters could be cut."""
    if hit is None or hit[0] or i + hit[2] >= len(chars) or longest_match(chars, i + hit[2], table, places, True):
        return hit
    for k in range(hit[2] - 1, 0, -1):
        kind = table.phrases.get(tuple(chars[i : i + k]))
        if kind is not None:  # a shorter filler, or a word of a class (で + すみません, not です + a stray みません)
            after = longest_match(chars, i + k, table, places, True)
            if after is not None and k + after[2] > hit[2]:
                return kind, "", k
    return hit


def tokens_ja(text: str, table: WordTable, places: PlaceLexicon) -> list[Token]:
    chars = [ch for ch in text if not ch.isspace()]
    janome = _Words("".join(chars))
    out: list[Token] = []
    i = 0
    while i < len(chars):
        ahead = "".join(chars[i : i + 12])
        floor = floor_ja(ahead) if chars[i] in _FLOOR_STARTS else None
        if floor is not None and not _place_within(chars, i, floor[1], table, places):
            out.append(Token("FLOOR", ahead[: floor[1]], floor=floor[0], start=i, end=i + floor[1]))
            i += floor[1]
            continue
        after_place = bool(out) and out[-1].kind == "PLACE" and out[-1].end == i
        numbered = _JA_KANA_NUMBER.match(ahead) if after_place else None
        if not after_place and chars[i] in "いさよご":  # the first kana of a number before its place
            numbered = _JA_KANA_BEFORE.match(ahead)
        if numbered:  # 寝室にばん, さんばんの寝室: a number with 番 (rule 6), not the particle に or the さん of a name
            n = len(numbered.group(0))
            out.append(Token("WORD", ahead[:n], start=i, end=i + n))
            i += n
            continue
        duration = _JA_DURATION.match(ahead)
        if duration:
            n = len(duration.group(0))
            later = _JA_LATER.match(ahead, n)
            if later:  # 10分後に: a delay, refused whole (not a length of a wait)
                n = later.end()
                out.append(Token("DELAY", ahead[:n], start=i, end=i + n))
                i += n
                continue
            out.append(Token("DURATION", duration.group(0), seconds=_ja_seconds(duration), start=i, end=i + n))
            i += n
            continue
        hit = _match(chars, i, out, table, places, janome)
        if hit is not None:
            kind, value, n = hit
            if kind:
                words = (value,) if kind == "PLACE" else ()
                out.append(Token(kind, "".join(chars[i : i + n]), words, start=i, end=i + n))
            elif "".join(chars[i : i + n]) in APOLOGIES and after_a_place(out):
                out.append(Token("_APOLOGY", "".join(chars[i : i + n]), start=i, end=i + n))
            elif _hesitation(chars, i, n, out, table, places):
                out.append(Token("HESITATION", "".join(chars[i : i + n]), start=i, end=i + n))
            i += n
            continue
        last = out[-1] if out else None
        noun = next((w for w in table.nouns if "".join(chars[i : i + len(w)]) == w), None)
        if noun is not None and last is not None and last.kind == "PLACE" and last.end == i:
            out[-1] = Token("PLACE", last.surface + noun, last.words, start=last.start, end=i + len(noun))
            i += len(noun)
            continue
        if last is not None and last.kind == "WORD" and last.end == i:
            out[-1] = Token("WORD", last.surface + chars[i], start=last.start, end=i + 1)
        else:
            out.append(Token("WORD", chars[i], start=i, end=i + 1))
        i += 1
    return held(apologies(reasons(_nearest_to(out))))


_PAUSES = frozenset("、,。.!！?？…‥ー〜~")


def _hesitation(chars: list[str], i: int, n: int, out: list[Token], table: WordTable, places: PlaceLexicon) -> bool:
    """Whether the filler ``chars[i : i + n]`` stands between two places said bare, nothing but pauses around it
    (りびんぐ… えっとね… きっちん！): the speaker searched for the word, and whether the second place replaces the first
    or follows it is a guess, as "the kitchen... uh... the dining room" is in English; kept, to be refused."""
    before = [t for t in out if t.kind != "COMMA"]
    if not before or before[-1].kind != "PLACE":
        return False
    k = i + n
    after = None
    while k < len(chars):
        if chars[k] in _PAUSES:
            k += 1
            continue
        after = longest_match(chars, k, table, places, True)
        if after is None or after[0]:
            break
        k += after[2]  # another filler (えっと|ね)
    if after is None or after[0] != "PLACE" or after[1] in before[-1].words:
        return False  # 風呂ね風呂場: the same place said again is no hesitation between two
    nxt = k + after[2]
    return nxt >= len(chars) or chars[nxt] in _PAUSES


def _match(
    chars: list[str], i: int, out: list[Token], table: WordTable, places: PlaceLexicon, janome: _Words
) -> tuple[str, str, int] | None:
    """The entry matched at ``chars[i]`` (the longest, a filler fitted to what follows it), or None where the
    match is a piece of a word janome knows around it."""
    hit = _filler_fitting(chars, i, table, places, longest_match(chars, i, table, places, True))
    if hit is not None and not hit[0] and i + hit[2] < len(chars) and chars[i + hit[2]] in _SMALL_KANA:
        hit = _shorter_filler(chars, i, hit, table, places)
    if hit is None or not _loose(chars, i, hit[2], out, table, places):
        return hit
    if not hit[0] and _in_a_noun(chars, i, hit[2], janome.nouns(), out, table, places):
        return None  # おばあちゃん, おなか: a filler's characters inside a noun janome knows are the noun's
    if hit[2] == 1 and hit[0] in _PARTICLES and janome.inside_predicate(i):
        return None  # で of できる, と of とる: a particle's character inside a verb or adjective janome knows
    return hit


class _Words:
    """janome's words of a sentence, analysed once and only when asked: most sentences never need them."""

    def __init__(self, text: str) -> None:
        self.text = text
        self._nouns: list[tuple[int, int]] | None = None
        self._predicates: list[tuple[int, int]] | None = None

    def nouns(self) -> list[tuple[int, int]]:
        if self._nouns is None:
            self._nouns = _nouns(self.text)
        return self._nouns

    def inside_predicate(self, i: int) -> bool:
        if self._predicates is None:
            self._predicates = _nouns(self.text, ("動詞", "形容詞"))
        return any(a <= i < b for a, b in self._predicates)


def _loose(chars: list[str], i: int, n: int, out: list[Token], table: WordTable, places: PlaceLexicon) -> bool:
    """Whether a match may be a piece of a word around it: an unknown word or a one-character match runs up to it,
    or no entry but a filler starts right after it (お|ば|あ|ちゃん, お|か|あ|さん, すぐ|で|きる); a match between
    two words the table knows is a word of its own, and janome is not asked."""
    last = out[-1] if out else None
    glued = (
        last is not None
        and last.end == i
        and (last.kind == "WORD" or last.kind != "PLACE" and last.end - last.start == 1)
    )
    if glued or i + n >= len(chars):
        return glued
    after = longest_match(chars, i + n, table, places, True)
    return after is None or not after[0]


_PARTICLES = frozenset({"DE", "AND", "ALTERNATIVE"})
"""Classes of one-character particles (で, と, や, か) that a verb or adjective may begin or hold (できる, とる)."""


def _nouns(text: str, parts: tuple[str, ...] = ("名詞",)) -> list[tuple[int, int]]:
    """(start, end) of each word of janome's dictionary of the parts of speech ``parts`` (nouns unless said) and
    more than one character in ``text`` (spaces left out), as janome segments it."""
    from spcotmhp.language.text import _tokenizer

    spans, at = [], 0
    for m in _tokenizer().tokenize(text):
        if m.part_of_speech.startswith(parts) and m.node_type == "SYS_DICT" and len(m.surface) > 1:
            spans.append((at, at + len(m.surface)))
        at += len(m.surface)
    return spans


def _in_a_noun(
    chars: list[str],
    i: int,
    n: int,
    nouns: list[tuple[int, int]],
    out: list[Token],
    table: WordTable,
    places: PlaceLexicon,
) -> bool:
    """Whether the filler ``chars[i : i + n]`` lies inside a noun janome knows (お|ば|あ|ちゃん, お|な|か) that
    overlaps no place or longer word matched before it and holds no start of a place or of a word of a class after
    the filler (a one-character word of a class before it, か of おかあさん, is the noun's character too):
    where janome's noun runs into a word the table knows (その|もの|おき: ものおき; あい|や: いや), the table wins."""
    for a, b in nouns:
        taken = any(t.kind == "PLACE" or t.kind != "WORD" and t.end - t.start > 1 for t in out if t.end > a)
        if taken or not (a <= i < b and (a < i or i + n < b)):
            continue
        if not any(_starts_word(chars, k, table, places) for k in range(i + 1, b)):
            return True
    return False


def _starts_word(chars: list[str], k: int, table: WordTable, places: PlaceLexicon) -> bool:
    hit = longest_match(chars, k, table, places, True)
    return hit is not None and bool(hit[0])


def _nearest_to(out: list[Token]) -> list[Token]:
    """A place with に right before a word of the nearest (風呂に最寄りの寝室, 風呂に近くの寝室) says what the nearest
    is near, as 風呂に一番近い does (CLOSEST): に there marks the relation's place, not a place to go to."""
    kept: list[Token] = []
    for t in out:
        marked = len(kept) >= 2 and kept[-1].kind == "GOAL" and kept[-1].surface == "に" and kept[-2].kind == "PLACE"
        if t.kind == "NEAREST" and marked:
            mark = kept.pop()
            kept.append(Token("CLOSEST", mark.surface + t.surface, start=mark.start, end=t.end))
            continue
        kept.append(t)
    return kept


def _shorter_filler(
    chars: list[str], i: int, hit: tuple[str, str, int], table: WordTable, places: PlaceLexicon
) -> tuple[str, str, int]:
    """A filler that would leave a character no word starts with (ねえ|っと, said ね + えっと) gives way to a
    shorter filler there, so the word after it keeps its first character; else the longest stays."""
    for m in range(hit[2] - 1, 0, -1):
        short = longest_match(chars[: i + m], i, table, places, True)
        if short is not None and not short[0] and chars[i + short[2]] not in _SMALL_KANA:
            return short
    return hit


def _place_within(chars: list[str], i: int, n: int, table: WordTable, places: PlaceLexicon) -> bool:
    """Whether a place word at least ``n`` characters long starts at ``chars[i]`` (地下室 is a room, not 地下)."""
    hit = longest_match(chars, i, table, places, True)
    return hit is not None and hit[0] == "PLACE" and hit[2] >= n


_NO_WORD_START = frozenset("っゃゅょぁぃぅぇぉゎッャュョァィゥェォヮーんン")
"""Characters no Japanese word starts with (small kana, the long-vowel mark, ん): an unknown run starting with one
is glued to the one-character word before it, so that a message names the word as written (や+っばり: やっばり)."""
_SMALL_KANA = frozenset("っゃゅょぁぃぅぇぉゎッャュョァィゥェォヮ")
"""Small kana: characters no word starts with and no filler is followed by (ね|えっと may be matched ねえ|っと)."""


def glue_ja(items: list[Token]) -> list[Token]:
    """Japanese: one-character words that belong to an unknown word around them (module docstring) become part of
    it; か is a choice only between two places (キッチンかトイレ), elsewhere a character of a word (静か)."""
    out: list[Token] = []
    for k, it in enumerate(items):
        nxt = items[k + 1] if k + 1 < len(items) else None
        prev = out[-1] if out else None
        loose = (
            it.kind == "ALTERNATIVE"
            and it.surface == "か"
            and not (prev is not None and prev.kind == "PLACE" and nxt is not None and nxt.kind == "PLACE")
        )
        starts_word = (
            it.kind == "WORD" and it.surface[0] in _NO_WORD_START and prev is not None
            and prev.kind not in ("PLACE", "WORD") and len(prev.surface) == 1 and prev.end == it.start
        )  # fmt: skip
        if starts_word and prev is not None:
            out[-1] = Token("WORD", prev.surface + it.surface, start=prev.start, end=it.end)
        elif loose or (it.kind == "WORD" and prev is not None and prev.kind == "WORD" and prev.end == it.start):
            if prev is not None and prev.kind == "WORD" and prev.end == it.start:
                out[-1] = Token("WORD", prev.surface + it.surface, start=prev.start, end=it.end)
            else:
                out.append(Token("WORD", it.surface, start=it.start, end=it.end))
        else:
            out.append(it)
    return out


def _ja_seconds(match: re.Match) -> float:
    """Seconds of a Japanese duration: digits or kanji numerals up to 九十九 (二十, 三十五), then 秒 / 分 / 時間."""
    number, unit = match.group(1), match.group(2)
    if number == "半":  # 半時間: half an hour
        return 0.5 * _JA_UNITS[unit]
    half = 0.5 * _JA_UNITS[unit] if match.group(3) else 0.0  # 1分半: a minute and a half
    if number[0].isdigit():
        return float(number) * _JA_UNITS[unit] + half
    tens, ten, ones = number.partition("十")
    if not ten:
        value = _KANJI_DIGITS.get(number, 0)
    else:
        value = _KANJI_DIGITS.get(tens, 1 if not tens else 0) * 10 + _KANJI_DIGITS.get(ones, 0)
    return float(value) * _JA_UNITS[unit] + half


def join_no(items: list[Token]) -> list[Token]:
    """Japanese: two place names joined by a lone の are one name (玄関の廊下: the entrance corridor)."""
    out: list[Token] = []
    for it in items:
        if (
            it.kind == "PLACE" and len(out) >= 2 and out[-1].kind == "WORD" and out[-1].surface == "の"
            and out[-2].kind == "PLACE" and out[-1].start == out[-2].end and it.start == out[-1].end
        ):  # fmt: skip
            no = out.pop()
            last = out[-1]
            out[-1] = Token("PLACE", last.surface + no.surface + it.surface, last.words + it.words, start=last.start,
                            end=it.end)  # fmt: skip
        else:
            out.append(it)
    return out


_JA_NUMBER_AFTER = re.compile(
    r"^(?:の)?(?:#|ナンバー|シャープ|no\.?)?(\d+|[一二三四五六七八九]|十[一二三四五六七八九]?|いち|に|さん|よん|ご)(?:番|ばん)?$"
)
"""A number after a place word: 寝室2, 寝室#2, 寝室の2番; ナンバー (number), シャープ (the name of '#', as a speech
recogniser spells it out) and No. say the sign the robot shows."""
_JA_NUMBER_BEFORE = re.compile(
    r"^(?:#?(\d+|[一二三四五六七八九]|十[一二三四五六七八九]?|いち|に|さん|よん|ご)(?:番|ばん)の?"
    r"|第(\d+|[一二三四五六七八九]|十[一二三四五六七八九]?)(?:の)?)$"
)
"""A number before a place word: 2番の寝室, and 第3寝室 (第 marks a number in a name, as "No." does: 第3会議室).
An ordinal (3番目の寝室, "the second bedroom") is no such number: it counts along something the map does not
hold (the frozen held-out corpora refuse it), so it stays refused."""
_JA_NUMERALS = {"いち": 1, "に": 2, "さん": 3, "よん": 4, "ご": 5}


def numbered_ja(items: list[Token]) -> list[Token]:
    """Rule 6 of :mod:`spcotmhp.language.lexicon`: a number with a place word names the instance the robot shows
    with it (寝室2, 寝室2番, 寝室#3, 寝室のさんばん, 2番の寝室: the plan's 寝室 #2). Kana numerals only with 番
    (ばん), which marks them as numbers (a lone に is a particle)."""
    out: list[Token] = []
    i = 0
    while i < len(items):
        it = items[i]
        nxt = items[i + 1] if i + 1 < len(items) else None
        pair = (it.kind, nxt.kind) if nxt is not None and it.end == nxt.start else ()
        if nxt is not None and pair in (("PLACE", "WORD"), ("WORD", "PLACE")):
            place, said = (it, nxt) if pair[0] == "PLACE" else (nxt, it)
            pattern = _JA_NUMBER_AFTER if pair[0] == "PLACE" else _JA_NUMBER_BEFORE  # 寝室2番 / 2番の寝室
            n = _ja_number(pattern.match(said.surface), said.surface)
            later = items[i + 2 : i + 4]
            if n == 1 and "一番" in said.surface and any(t.kind in _RELATIONS for t in later):
                n = None  # 寝室の一番トイレに近いとこ: 一番 is "most", said before the relation's place
            if n is not None:
                out.append(place._replace(surface=it.surface + nxt.surface, number=n, start=it.start, end=nxt.end))
                i += 2
                continue
        out.append(it)
        i += 1
    return out


def said_again_ja(items: list[Token]) -> list[Token]:
    """Rule 8 in Japanese: a number alone right after a correction word names that instance of the numbered place
    said just before the correction (寝室 #1 いや #2: 寝室 #2). Only a place said with a number is so corrected:
    "キッチン いや 2番" names nothing and stays refused."""
    if not any(t.kind == "CORRECTION" for t in items):
        return items
    out: list[Token] = []
    for it in items:
        kept = [t for t in out if t.kind != "COMMA"]  # 寝室1番、いや2番: the pause before the correction
        before = kept[-2] if len(kept) >= 2 else None
        if it.kind == "WORD" and before is not None and kept[-1].kind == "CORRECTION" and before.kind == "PLACE":
            n = _ja_number(NUMBER_AGAIN.match(it.surface), it.surface) if before.number is not None else None
            if n is not None:
                said = f"{before.words[-1]} #{n}"  # the label the robot shows
                out.append(before._replace(surface=said, number=n, start=it.start, end=it.end))
                continue
        out.append(it)
    return out


_OF = frozenset({"の", "のうち", "のうちで", "の中で", "のなかで", "の中の"})
_SUPERLATIVE = frozenset({"一番", "いちばん", "最も"})
_PRO_FORMS = frozenset({"ところ", "とこ", "の", "やつ", "ほう", "方", "部屋"})
_RELATIONS = frozenset({"CLOSEST", "FARTHEST", "NEXT_TO"})


def of_the_places_ja(items: list[Token]) -> list[Token]:
    """A relation said after the place it picks (rule 7 in Japanese): "X の(うち)、Y から一番遠いところ" (of the
    Xs, the one farthest from Y; ところ, とこ, の, やつ, ほう stand for the X) is "Y から一番遠い X", also with a
    pause for の (寝室、トイレに近いとこ) and after the X's own sentence (寝室に行って。キッチンから一番遠いやつね);
    一番 said before Y (寝室の 一番 トイレに近いとこ) belongs to the relation after Y. Anything else stays."""
    if any(t.kind in _SIZES for t in items):
        items = _size_after(items)
    if not any(t.kind in _RELATIONS for t in items):
        return items
    out = list(items)
    for k in range(len(out) - 3):
        x, of = out[k], out[k + 1]
        goal = of if of.kind == "GOAL" and out[k + 2].kind == "_STOP" else None  # 寝室に行って。…遠いやつね
        of_most = of.kind == "WORD" and of.surface in _OF_MOST  # 寝室の一番トイレに近いとこ
        if x.kind != "PLACE" or not (of.kind == "WORD" and of.surface in _OF or of_most or of.kind == "COMMA" or goal):
            continue
        m = k + 2 + (of.kind == "WORD" and out[k + 2].kind == "COMMA") + (goal is not None)
        m += m < len(out) and out[m].kind == "WORD" and out[m].surface in _SUPERLATIVE
        if m + 1 >= len(out) or out[m].kind != "PLACE" or out[m + 1].kind not in _RELATIONS:
            continue
        end, said = m + 2, ""
        while end < len(out) and out[end].kind in ("WORD", "AND") and said + out[end].surface in _PREFIXES:
            said += out[end].surface
            end += 1
        if said in _PRO_FORMS:  # the pro-form stands for the X: it is the X picked
            head = x._replace(start=out[end - 1].start, end=out[end - 1].end)
            return [*out[:k], out[m], out[m + 1], head, *([goal] if goal else []), *out[end:]]
    return out


_OF_MOST = frozenset("の" + s for s in _SUPERLATIVE)
_PREFIXES = frozenset(p[:n] for p in _PRO_FORMS for n in range(1, len(p) + 1))
_SIZES = frozenset({"LARGEST", "SMALLEST"})


def _size_after(items: list[Token]) -> list[Token]:
    """ "X(の) 一番小さいの" (寝室 いちばん ちいさい の: of the Xs the smallest one) is "一番小さい X": the size said
    after the place, with a pro-form standing for it (の, とこ, ところ, やつ, ほう; also "X のうちで、一番広いとこ",
    and 一番大きいの with the pro-form in the size's own word)."""
    for k in range(len(items) - 1):
        x = items[k]
        m = k + 1
        if m < len(items) and items[m].kind == "WORD" and items[m].surface in _OF:
            m += 1 + (items[m].surface == "のうち" and m + 1 < len(items) and items[m + 1].kind == "DE")
        elif m + 1 < len(items) and items[m].kind == "DE" and items[m + 1].kind in _SIZES:
            m += 1  # 寝室で一番大きいとこ: で as "among"
        m += m < len(items) and items[m].kind == "COMMA"
        if x.kind != "PLACE" or m >= len(items) or items[m].kind not in _SIZES or m == k + 1 and m + 1 >= len(items):
            continue
        end, said = m + 1, ""
        while end < len(items) and items[end].kind in ("WORD", "AND") and said + items[end].surface in _PREFIXES:
            said += items[end].surface
            end += 1
        own = not said and items[m].surface.endswith("の") and m > k + 1  # 寝室の一番大きいの
        if not (said in _PRO_FORMS or own) or end < len(items) and items[end].kind == "PLACE":
            continue
        last = items[end - 1]
        return [*items[:k], items[m], x._replace(start=last.start, end=last.end), *items[end:]]
    return items


def _ja_number(match: re.Match | None, surface: str) -> int | None:
    if match is None:
        return None
    said = next(g for g in match.groups() if g is not None)
    if said in _JA_NUMERALS:
        if "番" not in surface and "ばん" not in surface:
            return None
        return _JA_NUMERALS[said]
    if said.isdigit():
        n = int(said)
    else:
        tens, ten, ones = said.partition("十")
        n = (10 + _KANJI_DIGITS.get(ones, 0)) if ten else _KANJI_DIGITS.get(said, 0)
    return n if 1 <= n <= 99 else None


def number_said_ja(surface: str) -> int | None:
    """The instance number a word says alone (2番, #3, 三番だ), or None (rule 8's reading of a number)."""
    return _ja_number(NUMBER_AGAIN.match(surface), surface)
