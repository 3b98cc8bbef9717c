"""Text as words: one normalisation and one word splitter for everything people say (instructions, teaching
utterances, dataset rows), so that "ｋｉｔｃｈｅｎ", "KITCHEN" and "kitchen", or "ｷｯﾁﾝ" and "キッチン", are one word.

* :func:`normalise`: Unicode NFKC (full-width Latin letters and digits become ASCII, half-width katakana
  becomes full-width), case folding, and typographic apostrophes as "'".
* :func:`words`: English word units (letters and digits, inner apostrophes kept: "alice's"); Japanese as the
  speaker spaced it, or, when the text has no spaces, cut by the morphological analyser janome (its dictionary
  ships with it; loaded on first use, about 0.2 s) with consecutive nouns joined into one word, because a
  Japanese compound noun is written without a break and names one thing (子供+部屋 -> 子供部屋, 洗濯+室 ->
  洗濯室; janome's own entries already hold many such compounds).
* :func:`is_japanese`: whether a text holds kana or kanji.

>>> normalise("ＧＯ ｔｏ ｔｈｅ Ｋｉｔｃｈｅｎ"), normalise("ｷｯﾁﾝ"), normalise("Alice’s room")
('go to the kitchen', 'キッチン', "alice's room")
>>> words("This is Alice's room!", "en")
['this', 'is', "alice's", 'room']
>>> words("ここ は 書斎 です", "ja") == words("ここは書斎です", "ja") == ['ここ', 'は', '書斎', 'です']
True
"""

from __future__ import annotations

import functools
import re
import threading
import unicodedata
from typing import Any

_EN_WORD = re.compile(r"[^\W_]+(?:'[^\W_]+)*")
_CJK = re.compile(r"[\u3040-\u30ff\u3400-\u9fff]")
_APOSTROPHES = str.maketrans({"\u2019": "'", "\u2018": "'", "\u02bc": "'", "\uff07": "'"})
_JOINED_NOUNS = ("一般", "サ変接続", "固有名詞", "形容動詞語幹", "接尾", "副詞可能", "ナイ形容詞語幹")
"""janome (IPADIC) noun subclasses that continue a compound noun; pronouns (代名詞), dependent nouns (非自立)
and numbers (数) do not, so ここ, こと and ２ stay words of their own."""
_lock = threading.Lock()
_ARROWS = ((0x2190, 0x21FF), (0x27F0, 0x27FF), (0x2900, 0x297F), (0x2B00, 0x2BFF))
_LAUGH = re.compile(r"(?<=[\u3040-\u30ff\u3400-\u9fff!?。、])w+(?=[\s!?。、]|$)")


def without_pictographs(text: str) -> str:
    """``text`` with pictographs (emoji, dingbats: Unicode symbols "So" and their modifiers, joiners and variation
    selectors) and texting laughter ("w" after Japanese: 行っといてw) as spaces: they say how the speaker feels,
    never where to go. Arrows stay ("キッチン→風呂" orders two places). English units already drop them.

    >>> without_pictographs("キッチン行ってもらえる？😊"), without_pictographs("風呂→寝室ww")
    ('キッチン行ってもらえる？ ', '風呂→寝室 ')
    """
    out = []
    for ch in _LAUGH.sub(" ", text):
        code = ord(ch)
        arrow = any(lo <= code <= hi for lo, hi in _ARROWS)
        mark = unicodedata.category(ch) == "So" and not arrow or 0x1F3FB <= code <= 0x1F3FF or ch in "\u200d\ufe0f"
        out.append(" " if mark else ch)
    return "".join(out)


def normalise(text: str) -> str:
    """NFKC, case-folded, with typographic apostrophes as "'" (module docstring)."""
    return unicodedata.normalize("NFKC", text).translate(_APOSTROPHES).casefold()


def is_japanese(text: str) -> bool:
    """Whether ``text`` holds kana or kanji (after NFKC, half-width katakana included)."""
    return bool(_CJK.search(unicodedata.normalize("NFKC", text)))


def words(text: str, lang: str, segment: bool = True) -> list[str]:
    """The words of ``text`` (normalised): English word units, or Japanese words (module docstring). With
    ``segment`` False, Japanese is split at spaces only, as dataset rows are given (a row is one phrase per space,
    so a row without spaces is one word: 物置き)."""
    text = normalise(text)
    if lang == "ja":
        if not segment or any(ch.isspace() for ch in text.strip()):
            return text.split()
        return segment_ja(text)
    return _EN_WORD.findall(text)


def segment_ja(text: str) -> list[str]:
    """Japanese text without spaces cut into words by janome, consecutive nouns joined (module docstring);
    punctuation and symbols are dropped."""
    out: list[str] = []
    noun_run = False
    for token in _tokenizer().tokenize(text):
        pos = token.part_of_speech.split(",")
        if pos[0] == "記号" or not token.surface.strip():
            noun_run = False
            continue
        is_noun = pos[0] == "名詞" and pos[1] in _JOINED_NOUNS
        if is_noun and noun_run and out:
            out[-1] += token.surface
        else:
            out.append(token.surface)
        noun_run = is_noun
    return out


@functools.lru_cache(maxsize=4096)
def japanese_function_word(word: str) -> bool:
    """Whether janome reads ``word`` as one morpheme of a closed class (particle, auxiliary, pronoun,
    adnominal, conjunction, interjection, filler, symbol, dependent noun): words that never name a place.

    >>> japanese_function_word("は"), japanese_function_word("ここ"), japanese_function_word("書斎")
    (True, True, False)
    """
    morphemes = list(_tokenizer().tokenize(word))
    if len(morphemes) != 1:
        return False
    pos = morphemes[0].part_of_speech.split(",")
    closed = ("助詞", "助動詞", "連体詞", "接続詞", "感動詞", "フィラー", "記号")
    return pos[0] in closed or (pos[0] == "名詞" and pos[1] in ("代名詞", "非自立"))


def reading(word: str) -> str:
    """The katakana reading of a Japanese word that janome's dictionary holds as one entry ("" otherwise: a
    reading pieced together from parts may be wrong, 物置+き).

    >>> reading("風呂"), reading("物置き")
    ('フロ', '')
    """
    morphemes = list(_tokenizer().tokenize(unicodedata.normalize("NFKC", word)))
    if len(morphemes) != 1 or morphemes[0].reading in ("", "*"):
        return ""
    return str(morphemes[0].reading)


def _tokenizer() -> Any:
    """janome's tokenizer, built once per process (its dictionary loads on first use)."""
    global _TOKENIZER
    with _lock:
        if _TOKENIZER is None:
            from janome.tokenizer import Tokenizer

            _TOKENIZER = Tokenizer()
        return _TOKENIZER


_TOKENIZER: Any = None


_KANA_ONES = {"いち": 1, "いっ": 1, "に": 2, "さん": 3, "よん": 4, "ご": 5, "ろく": 6, "ろっ": 6, "なな": 7, "はち": 8,
              "はっ": 8, "きゅう": 9}  # fmt: skip
_KANA_LENGTH = re.compile(
    r"(?:(に|さん|よん|ご|ろく|なな|はち|きゅう)?(じゅう|じゅっ|じっ))?"
    r"(いち|いっ|に|さん|よん|ご|ろく|ろっ|なな|はち|はっ|きゅう)?(ぷん|ふん|びょう|じかん)(?!ご|あと|後)"
)
_KANA_UNITS = {"ぷん": "分", "ふん": "分", "びょう": "秒", "じかん": "時間"}


def kana_lengths(text: str) -> str:
    """Lengths of time written in kana, as a speech recogniser writes them (ごふん, いっぷん, じゅっぷん, にじゅっぷん,
    さんじゅうびょう, いちじかん), in digits (5分, 1分, 10分, 20分, 30秒, 1時間), as a number and its unit are read;
    a delay (じゅっぷんごに: ten minutes later) is left as said, to be refused quoting it.

    >>> kana_lengths("キッチンで ごふん まってて"), kana_lengths("にじゅっぷん"), kana_lengths("ふんいき")
    ('キッチンで 5分 まってて', '20分', 'ふんいき')
    """

    def digits(m: re.Match) -> str:
        tens_of, ten, ones, unit = m.groups()
        if not ten and not ones:
            return m.group(0)  # a unit alone: ふんいき is no length
        value = (_KANA_ONES.get(tens_of or "", 1) * 10 if ten else 0) + _KANA_ONES.get(ones or "", 0)
        return f"{value}{_KANA_UNITS[unit]}"

    return _KANA_LENGTH.sub(digits, text) if any(u in text for u in _KANA_UNITS) else text
