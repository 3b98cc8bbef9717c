"""Reading a teaching utterance: which name it teaches, or that it teaches none.

A teach is a *naming*: the person says what the place where the robot stands is called. Only the name is learned
(:func:`spcotmhp.teaching.teach.teach`); an utterance that names nothing ("hello", "is this the kitchen?", "this
isn't the study", "go to the kitchen") is refused with :class:`~spcotmhp.errors.NotANaming` rather than learned as
words. The rules, per language:

English (words as :func:`spcotmhp.language.text.words` gives them, punctuation kept as boundaries; contractions
expanded: "it's" -> "it is", "you're" -> "you are", "isn't" -> "is not", "let's" -> "let us"; hesitations
"um", "uh", "er", "hmm" dropped with their commas):

1. The utterance is cut into sentences at ``.``, ``!``, ``?`` and ``;``. A sentence that opens (after discourse
   words such as "ok", "so", "robot") with an interrogative or an auxiliary verb ("is this the kitchen", "where
   are we", "could this be ...") is a question and names nothing; a tag after a comma ("..., okay?") is not.
2. In the remaining sentences, in order, a *naming frame* is looked for: a copula after "this", "that", "it" or
   "here" (optionally "this room", "this one", "this here"; "=" counts as a copula), or an explicit naming
   ("this is called", "we call this", "let us call this room", "name this room", "this room's name is", "the name
   of this room is", "you are (now, currently) in", "the place you are in is", "welcome to", "remember this:",
   and the inverted "NAME, this is").
3. The name is the run of words after the frame, past a determiner ("the", "a", "my", ...), up to punctuation or a
   grammar word of the instruction word table (``grammars/en.json``: "now", "and", "please", ...), at most
   ``MAX_NAME_WORDS`` words; a number word, digits or an ordinal stays in the name ("aisle one", "room 101", "the
   first aisle": :mod:`spcotmhp.language.said_names`), and a number alone is no name. After a plain copula the
   complement must start with a determiner or a possessive ("this is the study", "this is Bob's room"): an English
   predicate that names a room takes one, and a bare complement is an adjective ("this is nice", "it's cold in
   here"), unless it ends in a number ("this is aisle one", "this is room 101"). A frame followed by "not" names
   nothing ("this isn't the study"); the first frame with a name wins ("this isn't the bath, it's the washroom").
4. With no frame, an utterance that is one noun phrase of at most ``MAX_NAME_WORDS`` words, none of them a grammar
   or greeting word, is a bare name ("Study.").

Japanese (words by janome, :mod:`spcotmhp.language.text`):

1. A question mark, the sentence-final particle か ("書斎かな"), an interrogative (どこ, 何, どれ, ...) or a negated
   copula (じゃない, ではない) names nothing; a negation followed by て ("トイレじゃなくて洗面所だよ") contrasts,
   and the name after it counts.
2. The name is the first noun phrase (nouns, a prefix お/ご, nouns joined by の, a verb stem inside a compound:
   物+置き) that is not the subject ("ここ", "この部屋": a pronoun or a noun after この/その/あの) and is followed by
   a copula or a naming ending (です, だ, でございます, な, よ, ね, って/と + 呼ぶ/言う/名付ける, に + なる, a full
   stop, or the end): "キッチンに行って" has none.
3. The model's words of the name are its words without particles (東の廊下: 東, 廊下); a number (digits, kanji
   numerals, 第 with one) belongs to the word after it (2号室, 第二会議室: one word each).

>>> read_naming("Here's the laundry room.").name, read_naming("ここは書斎です").name
('laundry room', '書斎')
>>> read_naming("is this the kitchen?")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
spcotmhp.errors.NotANaming: 'is this the kitchen?' is a question, not a naming: ...
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from spcotmhp.errors import NotANaming
from spcotmhp.language.numbers import number_word
from spcotmhp.language.text import is_japanese, normalise

MAX_NAME_WORDS = 4
"""The longest name read (words): "guest room", "alice's room", "walk in closet"."""

_HINT = "teach by saying the place's name, e.g. 'this is the kitchen'"
_HINT_JA = "場所の名前を言ってください（例: 'ここはキッチンです'）"


@dataclass(frozen=True)
class Naming:
    """A name read from a teaching utterance: the name as said (normalised) and its words for the model."""

    name: str
    words: tuple[str, ...]


def read_naming(text: str, lang: str | None = None) -> Naming:
    """The name ``text`` teaches (module docstring); NotANaming when it teaches none."""
    lang = lang or ("ja" if is_japanese(text) else "en")
    if lang == "ja":
        return _read_ja(text)
    return _read_en(text)


# ---- English -------------------------------------------------------------------------------------------------
_TOKEN = re.compile(r"[^\W_]+(?:'[^\W_]+)*|\.\.\.|…|[.,!?;:=\-–—]")
_SENTENCE_END = {".", "!", "?", ";", "...", "…"}
_PUNCT = _SENTENCE_END | {",", ":", "-", "–", "—", "="}
_CONTRACTIONS = {
    "it's": "it is",
    "here's": "here is",
    "that's": "that is",
    "this's": "this is",
    "you're": "you are",
    "we're": "we are",
    "they're": "they are",
    "isn't": "is not",
    "aren't": "are not",
    "wasn't": "was not",
    "let's": "let us",
    "what's": "what is",
    "where's": "where is",
    "i'm": "i am",
}
_HESITATIONS = {"um", "umm", "uh", "uhm", "er", "erm", "hmm", "hm", "ah", "eh"}
_DISCOURSE = {"ok", "okay", "so", "well", "right", "robot", "hey", "and", "now", "oh", "fyi", "yes", "yeah"}
_QUESTION_OPENERS = {
    "is", "are", "was", "were", "am", "do", "does", "did", "can", "could", "would", "will", "shall", "should",
    "may", "might", "what", "where", "which", "who", "whose", "how", "why", "when",
}  # fmt: skip
_DETERMINERS = {"the", "a", "an", "my", "our", "your", "his", "her", "their", "its"}
_GREETINGS = {"thank", "thanks", "you", "yes", "no", "ok", "okay", "bye", "sorry", "please", "nice", "good", "great"}
_SUBJ = r"(?:this|that|it|here)(?: (?:room|place|area|spot|space|one))?(?: here)?"
_NOUN = r"(?: (?:room|place|area|spot|space|one))?"
_EXPLICIT = [
    rf"\b{_SUBJ} (?:is )?(?:called|named)\b",
    rf"\b(?:we|i|they|you|people) (?:call|name) (?:this|it|that){_NOUN}\b",
    rf"\blet us (?:call|name) (?:this|it|that){_NOUN}\b",
    rf"^(?:(?:ok|okay|so|now|please|robot) )*(?:call|name) (?:this|it|that){_NOUN}\b",
    r"\b(?:this|that|the) (?:room|place|area|spot)'s name is\b",
    r"\bthe name of (?:this|that|the) (?:room|place|area|spot) is\b",
    r"\b(?:you|we) are (?:now |currently |right now )?in\b",
    r"\bthe (?:place|room|spot) (?:you|we) are in is\b",
    r"\bwelcome to\b",
    rf"\bremember (?:this|that){_NOUN}(?: is)? :",
    rf"\b{_SUBJ} =",
]
_PLAIN = [rf"\b{_SUBJ} is\b"]
_INVERTED = re.compile(r"^(?:the )?((?:[^\s,]+ ){0,3}[^\s,]+) , (?:this|it) is$")


def _en_tokens(text: str) -> list[str]:
    raw = _TOKEN.findall(normalise(text))
    out: list[str] = []
    for i, tok in enumerate(raw):
        stem = tok[:-2] if tok.endswith("'s") else ""
        nxt = raw[i + 1] if i + 1 < len(raw) else ""
        if stem in ("one", "room", "place", "area", "spot") and i and raw[i - 1] in ("this", "that") and nxt != "name":
            tok = f"{stem} is"  # "this one's the utility room"; "this room's name is" keeps its possessive
        out.extend(_CONTRACTIONS.get(tok, tok).split())
    keep: list[str] = []
    for i, tok in enumerate(out):  # hesitations go, with the commas around them
        if tok in _HESITATIONS:
            if keep and keep[-1] == ",":
                keep.pop()
            continue
        if tok == "," and i > 0 and out[i - 1] in _HESITATIONS:
            continue
        keep.append(tok)
    return keep


def _sentences(tokens: list[str]) -> list[list[str]]:
    out: list[list[str]] = [[]]
    for tok in tokens:
        if tok in _SENTENCE_END:
            out.append([])
        else:
            out[-1].append(tok)
    return [s for s in out if s]


def _is_question(sentence: list[str]) -> bool:
    words = [w for w in sentence if w != ","]
    while words and words[0] in _DISCOURSE:
        words.pop(0)
    return bool(words) and words[0] in _QUESTION_OPENERS


def _grammar_words() -> frozenset[str]:
    from spcotmhp.language.lexicon import word_table

    return frozenset(w for w in word_table("en").function_words if " " not in w)


def _name_after(words: list[str], start: int, plain: bool) -> list[str] | None:
    """The name's words from ``words[start:]`` (rule 3), None when there is none."""
    grammar = _grammar_words()
    rest = words[start:]
    if rest[:1] == ["not"]:
        return None
    determiner = bool(rest) and rest[0] in _DETERMINERS
    if determiner:
        rest = rest[1:]
    possessive = bool(rest) and rest[0].endswith("'s") and rest[0] not in _CONTRACTIONS
    name: list[str] = []
    for w in rest:
        if w in _PUNCT or _grammar(w, grammar) or w in _DETERMINERS or len(name) == MAX_NAME_WORDS:
            break
        name.append(w)
    if plain and not determiner and not possessive and not _numbered(name):
        return None
    return name if _names(name) else None


def _grammar(word: str, grammar: frozenset[str]) -> bool:
    """Whether ``word`` ends a name: a grammar word of instructions that is not a number (rule 3: "aisle one",
    "the first aisle" keep their numbers, :mod:`spcotmhp.language.said_names`)."""
    return word in grammar and number_word(word) is None


def _names(words: list[str]) -> bool:
    """Whether ``words`` can be a name: some word is not a number ("one" alone, "the first", names nothing)."""
    return any(number_word(w) is None for w in words)


def _numbered(words: list[str]) -> bool:
    """A complement without a determiner that is a name ending in a number ("this is aisle one", "room 101", "bay
    3"): an adjective ("this is nice") is never followed by one."""
    return len(words) >= 2 and number_word(words[-1]) is not None and _names(words)


def _frame_names(sentence: list[str]) -> list[tuple[int, list[str]]]:
    """(position, name) of every naming frame of a sentence that yields a name."""
    text = " ".join(sentence)
    starts = [0]
    for w in sentence:
        starts.append(starts[-1] + len(w) + 1)
    found = []
    for plain, patterns in ((False, _EXPLICIT), (True, _PLAIN)):
        for pattern in patterns:
            for m in re.finditer(pattern, text):
                end = m.end()
                index = next((i for i, s in enumerate(starts) if s >= end), len(sentence))
                name = _name_after(sentence, index, plain)
                if name is not None:
                    found.append((m.start(), name))
    inverted = _INVERTED.match(text)
    if inverted:
        words = inverted.group(1).split()
        grammar = _grammar_words()
        if not any(_grammar(w, grammar) for w in words) and _names(words):
            found.append((0, words))
    return sorted(found, key=lambda item: item[0])


def _read_en(text: str) -> Naming:
    tokens = _en_tokens(text)
    quoted = " ".join(text.split())[:60]
    if not tokens:
        raise NotANaming(f"the utterance {quoted!r} has no words; {_HINT}")
    sentences = _sentences(tokens)
    questions = 0
    for sentence in sentences:
        if _is_question(sentence):
            questions += 1
            continue
        names = _frame_names(sentence)
        if names:
            return _naming(names[0][1], "en")
    words = [w for w in tokens if w not in _PUNCT]
    grammar = _grammar_words()
    bare = [w for w in words if w not in _DETERMINERS]
    if (
        not questions
        and len(sentences) == 1
        and "," not in tokens
        and 1 <= len(bare) <= MAX_NAME_WORDS
        and not any(_grammar(w, grammar) or w in _GREETINGS for w in bare)
        and _names(bare)
    ):
        return _naming(bare, "en")
    if questions:
        raise NotANaming(f"{quoted!r} is a question, not a naming: {_HINT}")
    raise NotANaming(f"{quoted!r} names no place (no 'this is the ...' with a name); {_HINT}")


def _naming(words: list[str], lang: str) -> Naming:
    name = ("" if lang == "ja" else " ").join(words)
    return Naming(name, tuple(words) if lang == "en" else _ja_words(name))


# ---- Japanese ------------------------------------------------------------------------------------------------
_INTERROGATIVES = {"どこ", "何", "なに", "なん", "どれ", "どちら", "どっち", "だれ", "誰", "いくつ"}
_ENDINGS_AUX = {"です", "だ", "でし", "で", "な", "じゃ"}  # copula forms (助動詞) after a name
_NAMING_VERBS = ("呼", "よ", "言", "い", "名付", "なづ", "名づ")
_QUOTES = str.maketrans({c: " " for c in "「」『』\"'“”"})


def _ja_tokens(text: str) -> list[tuple[str, str, str]]:
    from spcotmhp.language.text import _tokenizer

    out = []
    for t in _tokenizer().tokenize(normalise(text).translate(_QUOTES)):
        pos = t.part_of_speech.split(",")
        if t.surface.strip():
            out.append((t.surface, pos[0], pos[1]))
    return out


def _ja_refusal(tokens: list[tuple[str, str, str]], quoted: str) -> NotANaming | None:
    for i, (s, p, sub) in enumerate(tokens):
        if s in ("?", "？") or s in _INTERROGATIVES or (p == "助詞" and s in ("か", "かしら") and "終助詞" in sub):
            return NotANaming(f"{quoted!r} is a question, not a naming: {_HINT_JA}")
        negated = s in ("ない", "ありませ", "ねえ") and p in ("助動詞", "形容詞")
        if negated and i > 0 and tokens[i - 1][0] in ("じゃ", "では", "は"):
            return NotANaming(f"{quoted!r} says what the place is not, not its name: {_HINT_JA}")
    return None


def _ja_is_ending(tokens: list[tuple[str, str, str]], i: int) -> bool:
    """Whether the tokens from ``i`` on end a naming (a copula, a sentence-final particle, a naming verb, the
    end)."""
    if i >= len(tokens):
        return True
    s, p, sub = tokens[i]
    nxt = tokens[i + 1][0] if i + 1 < len(tokens) else ""
    if p == "記号":
        return True
    if p == "助動詞" and s in _ENDINGS_AUX and s != "じゃ":
        return not (s == "で" and nxt not in ("ござい", "ござる", "す", "あり", "ある"))
    if p == "助詞" and "終助詞" in sub:
        return True
    if s in ("って", "と") and nxt.startswith(_NAMING_VERBS):
        return True
    return s == "に" and nxt.startswith(("なり", "なっ", "なる"))


def _ja_phrase(tokens: list[tuple[str, str, str]], i: int) -> int:
    """The end (exclusive) of the noun phrase starting at ``i`` (0 length: none)."""
    j = i
    while j < len(tokens) and tokens[j][1] == "接頭詞":
        j += 1
    start = j
    while j < len(tokens):
        s, p, sub = tokens[j]
        noun = p == "名詞" and sub not in ("代名詞", "非自立")
        joins = s == "の" and j > start and j + 1 < len(tokens) and tokens[j + 1][1] in ("名詞", "接頭詞")
        if noun or joins:
            j += 1
        elif p == "動詞" and j > start and tokens[j - 1][1] == "名詞" and _ja_is_ending(tokens, j + 1):
            j += 1  # a verb stem closing a compound noun: 物+置き, 物+干し
        else:
            break
    return j if j > start else i


def _read_ja(text: str) -> Naming:
    tokens = _ja_tokens(text)
    quoted = " ".join(text.split())[:60]
    if not tokens:
        raise NotANaming(f"the utterance {quoted!r} has no words; {_HINT_JA}")
    refusal = _ja_refusal(tokens, quoted)
    if refusal is not None:
        raise refusal
    i = 0
    while i < len(tokens):
        s, p, sub = tokens[i]
        end = _ja_phrase(tokens, i) if p in ("名詞", "接頭詞") else i
        if end == i:
            i += 1
            continue
        subject = i > 0 and tokens[i - 1][1] == "連体詞"
        phrase = tokens[i:end]
        if not subject and phrase[-1][0] != "の" and _ja_is_ending(tokens, end):
            return _naming(["".join(t[0] for t in phrase)], "ja")
        i = end
    raise NotANaming(f"{quoted!r} names no place (no 'ここは…です' with a name); {_HINT_JA}")


def _ja_words(name: str) -> tuple[str, ...]:
    """The model's words of a Japanese name: its words (:func:`spcotmhp.language.text.words`) without particles
    ("おばあちゃんの部屋" -> おばあちゃん, 部屋), or the name whole when it is one word."""
    from spcotmhp.language.text import japanese_function_word, words

    parts = [w for w in words(name, "ja") if not japanese_function_word(w)]
    glued: list[str] = []
    for w in parts:  # a number and a 第 belong to the word after them: 2号室, 101号室, 第二会議室
        if glued and _ja_number(glued[-1]):
            glued[-1] += w
        else:
            glued.append(w)
    return tuple(glued) or (name,)


_KANJI_DIGITS = frozenset("〇一二三四五六七八九十百千")


def _ja_number(word: str) -> bool:
    """Whether ``word`` is a number (digits, kanji numerals) or 第 / a number after 第, which glue to the next."""
    body = word[1:] if word.startswith("第") else word
    return not body or body.isdigit() or all(ch in _KANJI_DIGITS for ch in body)
