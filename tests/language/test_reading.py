"""The instruction grammars (spcotmhp/language/grammars/) and what their derivations mean: each grammar is
LALR(1) with no conflict (one derivation per sentence), its word classes and its terminals agree, fillers never
change a reading, and the readings of relations, speeds, waits, orders and refusals are as documented."""

from __future__ import annotations

import logging
from collections.abc import Iterator

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lark import Lark, logger

from spcotmhp.errors import (
    EmptyInstruction,
    InstructionError,
    InstructionTooLarge,
    MalformedInstruction,
    NotUnderstood,
    UnknownPlaceWord,
    UnsupportedPhrase,
)
from spcotmhp.language.lexicon import english_units
from spcotmhp.language.reading import LANGUAGES, grammar, read
from spcotmhp.language.table import word_table
from tests.helpers.corpus import DATA, rows
from tests.helpers.vocabulary import PLACE_WORDS_EN, PLACE_WORDS_JA

EN = PLACE_WORDS_EN
JA = PLACE_WORDS_JA


@pytest.mark.parametrize("lang", LANGUAGES)
def test_grammar_is_lalr1_without_any_conflict(lang):
    """Lark resolves a shift/reduce conflict silently (it shifts) and only logs it: a conflict would be a sentence
    with two derivations, one of them never read. Build the grammar with Lark's debug log and find none."""
    records: list[str] = []
    handler = logging.Handler()
    handler.emit = lambda record: records.append(record.getMessage())  # type: ignore[method-assign]
    logger.addHandler(handler)
    old = logger.level
    logger.setLevel(logging.DEBUG)
    try:
        source = grammar(lang).source_grammar
        Lark(source, parser="lalr", lexer="basic", debug=True)  # type: ignore[arg-type]
    finally:
        logger.setLevel(old)
        logger.removeHandler(handler)
    assert not [r for r in records if "conflict" in r.lower()], records


@pytest.mark.parametrize("lang", LANGUAGES)
def test_word_classes_and_terminals_agree(lang):
    """Every terminal the grammar declares is a word class of the table (or one the lexicon makes: PLACE, DURATION,
    FLOOR, FLOOR_TO, WORD), and every class
    of the table is either a terminal or a refusal (which no rule accepts)."""
    table = word_table(lang)
    terminals = {s.name for rule in grammar(lang).rules for s in rule.expansion if s.is_term}
    classes = set(table.surfaces) - {"FILLER"}
    assert terminals - classes <= {"PLACE", "DURATION", "FLOOR", "FLOOR_TO"}
    assert classes - terminals <= set(table.reasons) | set(table.misplaced), classes - terminals


def _understood() -> Iterator[tuple[str, str, list[str]]]:
    for path in (DATA / "instruction_corpus.csv", DATA / "heldout" / "instructions.csv"):
        for row in rows(path):
            lang = row["vocabulary"].rsplit("_", 1)[1]
            if not row["refused"] and row["vocabulary"] != "synthetic_en":
                yield row["text"], lang, EN if lang == "en" else JA


def _reading(text: str, words: list[str], lang: str):
    try:
        return read(text, words, lang)
    except InstructionError:
        return None


SENTENCES = [(t, lang, w) for t, lang, w in _understood()]
EN_FILLERS = sorted(word_table("en").fillers) + ["could you", "if you can", "um", "thank you", "when you get a chance"]
JA_FILLERS = ["ね", "えっと", "ちょっと", "ください", "ロボットさん", "すみません", "あの"]


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.data())
def test_a_filler_anywhere_never_changes_a_reading(data):
    """Issue 23: inserting any filler of the closed class at any word boundary of an understood sentence gives the
    same reading (English: between any two words, inside grammar phrases too; Japanese: between the grammar's
    tokens, as Japanese has no spaces to insert at)."""
    text, lang, words = data.draw(st.sampled_from(SENTENCES))
    before = _reading(text, words, lang)
    if before is None:
        return
    if lang == "en":
        units = english_units(text)
        at = data.draw(st.integers(0, len(units)))
        filler = data.draw(st.sampled_from(EN_FILLERS))
        changed = " ".join([*units[:at], filler, *units[at:]])
    else:
        from spcotmhp.language.lexicon import tokens

        toks = tokens(text, word_table("ja"), words)
        cuts = sorted({0, *(t.end for t in toks)})
        from spcotmhp.language.text import normalise

        chars = [c for c in normalise(text) if not c.isspace()]  # the tokens' ends count normalised characters
        at = data.draw(st.sampled_from(cuts))
        changed = "".join(chars[:at]) + data.draw(st.sampled_from(JA_FILLERS)) + "".join(chars[at:])
    assert _reading(changed, words, lang) == before, changed


def said(place) -> str:
    """A place as its place words, with its relation ("bedroom (closest to the bath)")."""
    words = " ".join(place.words)
    return words if place.relation is None else f"{words} ({place.relation.describe()})"


@pytest.mark.parametrize(
    "text, visit, avoid, not_goal, speed, waits",
    [
        ("go to the bedroom closest to the bath", ["bedroom (closest to the bath)"], [], [], None, ()),
        ("take me to the bedroom nearest the kitchen via the corridor, avoiding the living room",
         ["corridor", "bedroom (closest to the kitchen)"], ["living"], [], None, ()),
        ("go to the bedroom farthest away from the entrance", ["bedroom (farthest from the entrance)"], [], [], None,
         ()),
        ("the bedroom right next to the washroom, please", ["bedroom (next to the washroom)"], [], [], None, ()),
        ("go to the bedroom between the kitchen and the bath", ["bedroom (between the kitchen and the bath)"], [], [],
         None, ()),
        ("the biggest of the bedrooms", ["bedroom (largest)"], [], [], None, ()),
        ("go to the kitchen, staying away from the bedroom closest to it", ["kitchen"],
         ["bedroom (closest to the kitchen)"], [], None, ()),
        ("the bedroom nearest the kitchen, not the one nearest the bath", ["bedroom (closest to the kitchen)"], [],
         ["bedroom (closest to the bath)"], None, ()),
        ("hurry to the toilet", ["toilet"], [], [], "fast", ()),
        ("go slowly to the kitchen and wait there for half a minute", ["kitchen"], [], [], "slow", ((0, 30.0),)),
        ("wait in the hall for two minutes, then go to the bedroom", ["hall", "bedroom"], [], [], None, ((0, 120.0),)),
        ("go to the kitchen and wait there", ["kitchen"], [], [], None, ((0, None),)),
        ("go to the bath after the kitchen after the toilet", ["toilet", "kitchen", "bath"], [], [], None, ()),
        ("visit the hall after the storeroom, and the entrance after the hall", ["storeroom", "hall", "entrance"], [],
         [], None, ()),
        ("go to the bedroom through the corridor, not the entrance", ["corridor", "bedroom"], ["entrance"], [], None,
         ()),
        ("go to the bedroom, not the kitchen", ["bedroom"], [], ["kitchen"], None, ()),
        ("make a stop at the kitchen, then continue to the living room", ["kitchen", "living"], [], [], None, ()),
        ("take me to the bedroom, but first I need to use the toilet", ["toilet", "bedroom"], [], [], None, ()),
        ("go into one of the bedrooms", ["bedroom"], [], [], None, ()),
        ("ｇｏ ｔｏ ｔｈｅ ｋｉｔｃｈｅｎ", ["kitchen"], [], [], None, ()),
    ],
)  # fmt: skip
def test_english_readings(text, visit, avoid, not_goal, speed, waits):
    r = read(text, EN, "en")
    assert [said(p) for p in r.visit] == visit
    assert [said(p) for p in r.avoid] == avoid
    assert [said(p) for p in r.not_goal] == not_goal
    assert (r.speed, r.waits) == (speed, waits)


@pytest.mark.parametrize(
    "text, visit, avoid, speed, waits",
    [
        ("キッチンに一番近い寝室に行って", ["寝室 (closest to the キッチン)"], [], None, ()),
        ("廊下を通って、風呂に一番近い寝室に行って。キッチンは避けてね",
         ["廊下", "寝室 (closest to the 風呂)"], ["キッチン"], None, ()),
        ("キッチンと風呂の間の寝室に行って", ["寝室 (between the キッチン and the 風呂)"], [], None, ()),
        ("一番大きい寝室に急いで行って", ["寝室 (largest)"], [], "fast", ()),
        ("洗面所で2分待ってから寝室に行って", ["洗面所", "寝室"], [], None, ((0, 120.0),)),
        ("ここは書斎ですじゃなくて", None, None, None, None),
        ("ｷｯﾁﾝに行って", ["キッチン"], [], None, ()),
        ("おふろに行って", ["風呂"], [], None, ()),
        ("物置に行ってください", ["物置き"], [], None, ()),
        ("トイレの後でキッチンの後で寝室に行って", ["トイレ", "キッチン", "寝室"], [], None, ()),
    ],
)  # fmt: skip
def test_japanese_readings_without_spaces(text, visit, avoid, speed, waits):
    if visit is None:
        with pytest.raises(InstructionError):
            read(text, JA, "ja")
        return
    r = read(text, JA, "ja")
    assert [said(p) for p in r.visit] == visit
    assert [said(p) for p in r.avoid] == avoid
    assert (r.speed, r.waits) == (speed, waits)


@pytest.mark.parametrize(
    "text, error, words",
    [
        ("go past the dining room", UnsupportedPhrase, "names only places to pass"),
        ("go to the bedroom at the end of the corridor", UnsupportedPhrase, "'at the end of'"),
        ("go to the bedroom closest to the kitchen and the bath", UnsupportedPhrase, "'and' after"),
        ("go slowly to the kitchen, then hurry to the bath", UnsupportedPhrase, "two speeds"),
        ("go to the entrance and wait there until the baby sleeps", UnsupportedPhrase, "'until'"),
        ("go to the toilet and wait, then go to the bedroom", UnsupportedPhrase, "'wait' between two places"),
        ("go to the kitchen, no wait", UnsupportedPhrase, "names nothing after it"),
        ("go to the kitchen, sorry, via the hall", UnsupportedPhrase, "no place to pass was said before"),
        ("no kitchen, go to the bath", UnsupportedPhrase, "'no' corrects"),
        ("actually, go to the bath", None, "bath"),
        ("go to all the bedrooms", UnsupportedPhrase, "'all bedrooms' asks for every place"),
        ("go to my bedroom", UnsupportedPhrase, "'my'"),
        ("go to the bedroom with the big window", UnknownPlaceWord, "'with the big window'"),
        ("go to the kitchen when dinner is ready", UnsupportedPhrase, "'when' makes"),
        ("go to the bedroom avoiding", MalformedInstruction, "'avoiding' is followed by no known place word"),
        ("avoid the kitchen", EmptyInstruction, "names no place to go to"),
        ("go to the kitchen and wait there for 2 hours", InstructionTooLarge, "longer than"),
        ("Wait in the hall for two hours.", InstructionTooLarge, "'for two hours' asks for a wait of 7200 s"),
        ("in ten minutes go to the living room", UnsupportedPhrase, "'in ten minutes' asks to start later"),
        ("follow me to the kitchen", NotUnderstood, "'follow me' is not understood"),
        ("go to the entrance and open the door", NotUnderstood, "'open the door' is not understood"),
        ("go to the bedroom with the window", NotUnderstood, "'with the window' is not understood"),
    ],
)
def test_refusals_name_what_cannot_be_honoured(text, error, words):
    if error is None:
        assert words in [p.label for p in read(text, EN, "en").visit]
        return
    with pytest.raises(error) as info:
        read(text, EN, "en")
    assert words in str(info.value)


@pytest.mark.parametrize("lang", LANGUAGES)
def test_the_stored_tables_are_the_grammars(lang):
    """grammars/<lang>.table.json (read instead of building the table, about 30 times faster on a process's first
    instruction) was written from the grammar as it is (its SHA-256; after editing a .lark file run
    ``python -m spcotmhp.language.reading``), and derives what Lark's own parser derives, tree for tree and refusal
    for refusal, on every sentence of the corpora (Lark numbers its states differently from one process to the
    next, so the files are compared by what they do)."""
    import hashlib
    import json
    from importlib import resources

    from lark import Token as LarkToken
    from lark.exceptions import UnexpectedInput

    from spcotmhp.language.lexicon import tokens
    from spcotmhp.language.reading import _NoDerivation, _source, derive

    folder = resources.files("spcotmhp.language") / "grammars"
    stored = json.loads((folder / f"{lang}.table.json").read_text(encoding="utf-8"))
    assert stored["source_sha256"] == hashlib.sha256(_source(lang).encode()).hexdigest()
    words = EN if lang == "en" else JA
    texts = [t for t, la, _ in SENTENCES if la == lang] + [r["text"] for r in rows(DATA / "instruction_corpus.csv")]
    for text in texts:
        toks = tokens(text, word_table(lang), words)
        try:
            ours = derive(lang, [t.kind for t in toks], [t.surface for t in toks])
        except _NoDerivation as exc:
            ours = exc.at
        interactive = grammar(lang).parse_interactive("")
        try:
            for i, t in enumerate(toks):
                interactive.feed_token(LarkToken(t.kind, t.surface, start_pos=i))
            theirs = interactive.feed_eof()
        except UnexpectedInput as exc:
            token = getattr(exc, "token", None)
            theirs = len(toks) if token is None or token.type == "$END" else token.start_pos
        assert ours == theirs, text


@pytest.mark.parametrize(
    ("text", "seconds"),
    [
        ("go to the bedroom and wait there for 3 s", 3.0),  # issue 36's acceptance, as it writes the length
        ("go to the bedroom and wait there for 3s", 3.0),
        ("go to the bedroom and wait 1.5 s", 1.5),
        ("go to the bedroom and wait 1 min 30 s", 90.0),
        ("go to the bedroom and wait for 1 h", 3600.0),
    ],
)
def test_a_length_in_si_symbols_is_read(text, seconds):
    """ "s" and "h" after a number are seconds and hours, as "sec" and "hours" are."""
    assert read(text, ["bedroom"], "en").waits == ((0, seconds),)


@pytest.mark.parametrize("text", ["go to the bedroom and wait there s", "go to the bedroom, wait h"])
def test_a_lone_s_or_h_is_no_unit(text):
    """Only right after a number: a lone "s" or "h" is a word not understood, not a length."""
    with pytest.raises(NotUnderstood):
        read(text, ["bedroom"], "en")


@pytest.mark.parametrize(
    ("text", "lang", "seconds"),
    [
        ("go to the bedroom, wait 1 minute 30 seconds", "en", 90.0),
        ("go to the bedroom and wait one minute and thirty seconds", "en", 90.0),
        ("go to the bedroom and wait 2 minutes and 5 seconds", "en", 125.0),
        ("寝室で1分30秒待って", "ja", 90.0),
    ],
)
def test_lengths_of_time_side_by_side_are_one_length(text, lang, seconds):
    """A length said in parts, each shorter than the one before, is their sum (it used to keep the first part)."""
    assert read(text, ["bedroom", "寝室"], lang).waits == ((0, seconds),)


@pytest.mark.parametrize(
    "text", ["go to the bedroom, wait 30 seconds 1 minute", "go to the bedroom, wait 1 minute 1 minute"]
)
def test_two_lengths_for_one_wait_are_refused(text):
    with pytest.raises(UnsupportedPhrase, match="two lengths"):
        read(text, ["bedroom"], "en")


def test_it_in_a_relation_is_the_last_place_of_another_name():
    """ "not the one nearest it" after "the bedroom farthest from the bath": it is the bath, not a bedroom."""
    r = read("Go to the bedroom farthest from the bath, not the one nearest it.", ["bedroom", "bath"], "en")
    assert [q.describe() for q in r.not_goal] == ["bedroom (closest to the bath)"]
    r = read("go to the kitchen and then the bedroom closest to it", ["bedroom", "kitchen"], "en")
    assert r.visit[-1].describe() == "bedroom (closest to the kitchen)"
    with pytest.raises(UnsupportedPhrase, match="'it' names no place"):
        read("go to the bedroom closest to it", ["bedroom"], "en")


@pytest.mark.parametrize(
    ("text", "lang", "visit", "waits"),
    [
        ("go to the kitchen and wait in the kitchen for 2 minutes", "en", ["kitchen"], ((0, 120.0),)),
        ("go to the bath via the kitchen, wait in the kitchen for a minute", "en", ["kitchen", "bath"], ((0, 60.0),)),
        (
            "go to the kitchen, then the bath, then wait in the kitchen for a minute",
            "en",
            ["kitchen", "bath", "kitchen"],
            ((2, 60.0),),
        ),
        ("キッチンへ行って、キッチンで2分待って", "ja", ["キッチン"], ((0, 120.0),)),
        ("まず寝室で待って", "ja", ["寝室"], ((0, None),)),
    ],
)
def test_waiting_at_the_place_just_named_is_one_visit(text, lang, visit, waits):
    """ "wait in the X" right after X was named to visit waits there; after another place it is a new stop."""
    words = ["kitchen", "bath", "キッチン", "寝室"]
    r = read(text, words, lang)
    assert [p.label for p in r.visit] == visit and r.waits == waits


@pytest.mark.parametrize(
    "text",
    [
        "could you go to the kitchen if you could you don't mind",
        "could you go to the kitchen if you if you can don't mind",
        "could if you can you go to the kitchen if you don't mind",
        "go to the kitchen when could you you're ready",
    ],
)
def test_a_filler_phrase_said_inside_another_leaves_both_out(text):
    """Found by the filler property below: the phrase said inside another is left out first, whichever it is."""
    assert [p.label for p in read(text, ["kitchen"], "en").visit] == ["kitchen"]


@pytest.mark.parametrize(
    "text, seconds",
    [
        ("wait in the bath for like two minutes", 120.0),
        ("wait in the bath for um two minutes", 120.0),
        ("wait in the bath for a a minute", 60.0),  # a filler "a" before "a minute"
        ("wait in the bath for uh half a minute", 30.0),
    ],
)
def test_fillers_between_for_and_a_length_belong_to_the_length(text, seconds):
    assert read(text, EN, "en").waits == ((0, seconds),)


@pytest.mark.parametrize(
    "text, waits_at",
    [
        ("Could you go to the washroom via the bath, and then wait there for half a minute?", "washroom"),
        ("go through the hall to the kitchen then wait there 2 minutes", "kitchen"),
        ("go to the kitchen, then go through the hall and wait there for a minute", "hall"),  # this step's place
        ("go to the kitchen via the hall and wait there for a minute", "kitchen"),
    ],
)
def test_wait_there_after_then_is_where_the_step_before_ends(text, waits_at):
    r = read(text, EN, "en")
    ((i, _),) = r.waits
    assert r.visit[i].words[0] == waits_at


def test_two_owners_share_the_plural_noun_after_them():
    words = ["alice's", "bob's", "corridor", "east", "kitchen", "room", "south"]
    r = read("go to the corridor between alice's and bob's rooms", words, "en")
    between = r.visit[-1].relation
    assert between is not None and [p.words for p in between.args] == [("alice's", "room"), ("bob's", "room")]


@pytest.mark.parametrize(
    "text, visit, avoid",
    [
        ("Go to the front door, oh never mind, go to the living room.", ["living room"], []),
        ("Could you go to the washroom? Actually, never mind that, the bath.", ["bath"], []),
        ("Go to the kitchen. Actually, forget the kitchen, go to the washroom.", ["washroom"], []),
        ("Head to the toilet. Oh, hang on, the storeroom instead.", ["storeroom"], []),
        ("kitchen. no. living room.", ["living room"], []),
    ],
)  # fmt: skip
def test_a_cancel_followed_by_a_whole_instruction_takes_back_all_before_it(text, visit, avoid):
    r = read(text, EN, "en")
    assert [p.label for p in r.visit] == visit and [p.label for p in r.avoid] == avoid
    assert any(h.startswith("took back") for h in r.heard)


@pytest.mark.parametrize(
    "text",
    [
        "go to the kitchen, never mind",  # nothing after it
        "Go to the dining room and avoid the kitchen... actually never mind, the kitchen's fine",  # no place to go
        "never mind, go to the kitchen",  # nothing before it to take back: read as said, or refused
    ],
)
def test_a_cancel_with_nothing_to_go_to_after_it_is_not_a_restart(text):
    try:
        r = read(text, EN, "en")
    except InstructionError:
        return
    assert not any(h.startswith("took back") for h in r.heard)


@pytest.mark.parametrize(
    "text, said",
    [
        ("Go to the kitchen at 6.", "'at 6'"),
        ("go to the living room at six", "'at six'"),
        ("at noon go to the hall", "'at noon'"),
    ],
)
def test_a_time_of_day_is_refused_quoting_it(text, said):
    with pytest.raises(UnsupportedPhrase, match=f"{said} is a time of day"):
        read(text, EN, "en")


@pytest.mark.parametrize(
    "text, speed",
    [
        ("Go to the kitchen, not through the dining room, and not too fast please", "slow"),
        ("go to the kitchen make it snappy", "fast"),
    ],
)
def test_speeds_said_in_other_words(text, speed):
    assert read(text, EN, "en").speed == speed


@pytest.mark.parametrize(
    "text, goal",
    [
        ("Go to the storeroom. Hmm no, make it the corridor.", "corridor"),
        ("which ever bedroom is nearest the toilet go there", "bedroom"),
        ("Can you move to the hallway so you're out of the way?", "corridor"),
        ("Next stop, kitchen!", "kitchen"),
    ],
)
def test_more_everyday_forms(text, goal):
    assert read(text, EN, "en").visit[-1].words[0] == goal


@pytest.mark.parametrize(
    "text, via, avoid",
    [
        ("go to the dining room via the kitchen no actually avoid the kitchen", [], ["kitchen"]),
        ("Avoid the living room, no actually it's fine, go through it to the dining room.", ["living"], []),
        ("go to the washroom and avoid the bath. actually it's fine, go through the bath.", ["bath"], []),
        # the entrance said again to avoid replaces going to it (the cancel's reading would be the same)
        ("Go to the entrance. No, scratch that, stay out of the entrance and go to the corridor.", [], ["entrance"]),
    ],
)
def test_a_place_said_again_with_another_role_after_a_correction_replaces_it(text, via, avoid):
    r = read(text, PLACE_WORDS_EN, "en")
    assert [p.words[0] for p in r.visit[:-1]] == via and [p.words[0] for p in r.avoid] == avoid
    assert any("instead of" in h for h in r.heard), "the explanation says what was replaced"


@pytest.mark.parametrize(
    "text",
    [
        "go to the dining room and avoid the kitchen actually it's fine you can go through the kitchen",  # may pass
        "take the corridor to the kitchen, oh, actually, skip the corridor and go through the hall",  # drop or avoid?
    ],
)
def test_a_role_change_with_two_readings_stays_refused(text):
    with pytest.raises(InstructionError):
        read(text, PLACE_WORDS_EN, "en")
