"""Talk around an instruction (spcotmhp/language/talk.py) and self-corrections (spcotmhp/language/walk.py,
Walk.correct): issue 34. Talk is passed over only where none of its words carries navigation meaning; inserting a
passed-over clause into any understood sentence never changes its reading, and a clause that does carry meaning
(a place, a time, a motion somewhere, an order) is never passed over."""

from __future__ import annotations

from dataclasses import replace

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from spcotmhp.errors import InstructionError, UnsupportedPhrase
from spcotmhp.language.reading import read
from tests.helpers.corpus import understood_heldout
from tests.helpers.vocabulary import PLACE_WORDS_EN, PLACE_WORDS_JA

EN = PLACE_WORDS_EN
JA = PLACE_WORDS_JA

TALK_EN = [
    "we're about to eat",
    "I'm hungry",
    "the baby's asleep",
    "the pizza guy is coming",
    "that'd be great",
    "mom says",
    "I'm cooking",
    "the kids are eating",
    "it's getting crowded",
    "thanks a bunch",  # asides (asides_en.py): talk without a statement's form
    "did you hear me?",
    "love",  # an address
    "huh",  # an interjection
    "gran here",  # a speaker introducing themselves
    "my dude",
    "grandad's asleep on the couch",  # a location of someone else's (talk.py, _elsewhere)
    "my mum is at work",
    "he wants to show his mates",  # a possessive before a thing
    "someone's at the door",  # a position noun saying where someone is
    "it's getting crowded in here",
    "Mr Ahmed is waiting",  # a title's name as the subject
    "I'm mopping the kitchen",  # statements of someone else naming a place (rule 3c of asides_en)
    "we're hoovering the lounge",
    "the kids are playing in the bedroom",
    "guests will be in the living room tonight",
    "grandma is in the bath",
]
"""Clauses the rule passes over (each says something about the world, with no place, time, order or motion)."""

NOT_TALK_EN = [
    "go to the garage",  # an order to an unknown place
    "we're going to the garage",  # a motion somewhere
    "at 6",  # a time
    "later",
    "I need you in the garage",
    "say dinner is ready",  # an order (an action the planner does not do)
    "the garage",  # a bare place phrase
    "not the kitchen either",
    "I know you just got to the bath",  # the talk's verb takes the place after it
    "I need you in the garage later",
    "faster",  # a speed (by its lemma: fast)
    "skip it",  # a word referring back to a place, and an order
    "turn that down",  # an order
    "don't stop",
    "come back",
    "stay there",
    "the other one",
    "I want it in the garage",  # "it" may be the robot: its location stays
    "he wants his room",  # a possessive before a place noun picks it
    "I need you here",  # where the robot is asked to be
    "I need you at the door",
]
"""Clauses that carry meaning: appended to an understood sentence they must not be passed over."""


UNDERSTOOD_EN = understood_heldout("3ldk_en", EN, "en")


def _meaning(text: str, words: list[str], lang: str):
    """A reading without what it says it did beyond the grammar (``heard``), or the refusal's class."""
    try:
        return replace(read(text, words, lang), heard=())
    except InstructionError as exc:
        return type(exc)


@pytest.mark.parametrize(
    "text, goal",
    [
        ("hey could you come to the dining room we're about to eat", "dining"),
        ("so um yeah if you could make your way to the kitchen that'd be great", "kitchen"),
        ("I'm hungry. Take me to the kitchen.", "kitchen"),
        ("i'm cooking come to the kitchen", "kitchen"),
        ("mom says go to the dining room", "dining"),
        ("go to the kitchen, the baby is asleep", "kitchen"),
    ],
)
def test_talk_around_an_instruction_is_passed_over_and_said(text, goal):
    r = read(text, EN, "en")
    assert [p.label.split()[0] for p in r.visit] == [goal]
    assert any(h.startswith("passed over") for h in r.heard), r.heard


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.data())
def test_inserting_talk_never_changes_a_reading(data):
    """Any passed-over clause, before or after any understood held-out sentence (as its own sentence or after a
    comma), leaves its reading as it was."""
    text = data.draw(st.sampled_from(UNDERSTOOD_EN))
    talk = data.draw(st.sampled_from(TALK_EN))
    where = data.draw(st.sampled_from(["before", "after", "after_comma"]))
    changed = {"before": f"{talk}. {text}", "after": f"{text.rstrip('.!?')}. {talk}.",
               "after_comma": f"{text.rstrip('.!?')}, {talk}"}[where]  # fmt: skip
    assert _meaning(changed, EN, "en") == _meaning(text, EN, "en"), changed


@pytest.mark.parametrize("talk", NOT_TALK_EN)
@pytest.mark.parametrize("text", ["go to the kitchen", "take me to the bedroom via the corridor"])
def test_a_clause_with_navigation_meaning_is_never_passed_over(text, talk):
    """(The "there" after a location passed over is tested below.)"""
    for changed in (f"{text}, {talk}", f"{text}. {talk}.", f"{talk}. {text}"):
        got = _meaning(changed, EN, "en")
        if isinstance(got, type):
            continue  # refused: fine
        assert got != _meaning(text, EN, "en"), f"{changed!r} was read as {text!r}: {talk!r} dropped"


@pytest.mark.parametrize(
    "text, visit, speed, heard",
    [
        ("go to the dining room no wait the living room", ["living"], None, "living room said instead of dining room"),
        ("uh the washroom um no sorry the toilet", ["toilet"], None, "toilet said instead of washroom"),
        ("go to the bath sorry i meant the bedroom", ["bedroom"], None, "bedroom said instead of bath"),
        ("go to the kitchen via the hall, sorry, the corridor", ["corridor", "kitchen"], None, "corridor said instead"),
        (
            "go to the kitchen through the hall no through the dining room",
            ["dining", "kitchen"],
            None,
            "dining room said",
        ),
        ("go fast to the living room actually no go slow", ["living"], "slow", "slow said instead"),
        ("go to the bath. sorry, I meant the bedroom.", ["bedroom"], None, "bedroom said instead of bath"),
    ],
)
def test_a_correction_replaces_the_place_of_the_same_role_said_before_it(text, visit, speed, heard):
    r = read(text, EN, "en")
    assert [p.label.split()[0] for p in r.visit] == visit
    assert r.speed == speed
    assert any(h.startswith(heard) for h in r.heard), r.heard


@pytest.mark.parametrize(
    "text",
    [
        "bedroom please, actually scratch that, not the bedroom, the living room",
        "bedroom sorry not the bedroom the living room",  # no pause: "bedroom living room" is no one name
    ],
)
def test_a_correction_after_a_negated_name_takes_the_place_meant_instead(text):
    """ "not the bedroom" repeats what the correction takes back (repairs_en.taken_back_en): no place not to end in
    of its own (six writers label these so, blind8, 13, 17, 21, 33, 44)."""
    r = read(text, EN, "en")
    assert [p.label.split()[0] for p in r.visit] == ["living"] and r.not_goal == ()
    assert "living room said instead of bedroom" in r.heard


@pytest.mark.parametrize(
    "text, words",
    [
        ("go to the kitchen, no wait", "names nothing after it"),
        ("go to the kitchen, sorry, via the hall", "no place to pass was said before"),
        ("no kitchen, go to the bath", "'no' corrects"),
    ],
)
def test_corrections_that_say_nothing_to_replace_are_refused(text, words):
    with pytest.raises(UnsupportedPhrase) as info:
        read(text, EN, "en")
    assert words in str(info.value)


def test_a_correction_opening_the_instruction_corrects_nothing():
    assert [p.label for p in read("Actually, go to the kitchen", EN, "en").visit] == ["kitchen"]


@pytest.mark.parametrize(
    "text, visit",
    [
        ("リビング、いや、やっぱり台所", ["キッチン"]),
        ("寝室に、いや、やっぱり物置に行って", ["物置き"]),
        ("キッチン行って いや違うダイニング", ["ダイニング"]),
        ("廊下を通って、いや、リビングを通ってキッチンへ", ["リビング", "キッチン"]),
    ],
)
def test_japanese_corrections(text, visit):
    r = read(text, JA, "ja")
    assert [p.words[0] for p in r.visit] == visit
    assert r.heard


@pytest.mark.parametrize(
    "text, visit",
    [
        ("納戸へ行っとくれ", ["物置き"]),
        ("台所行ったってや", ["キッチン"]),
        ("玄関まで行っといでや", ["玄関"]),
        ("あのさ洗面所行けたりする", ["洗面所"]),
        ("茶の間へ行きなさい", ["リビング"]),
        ("物置き行っとけ", ["物置き"]),  # the contraction of 行っておけ
        ("廊下に出てろ", ["廊下"]),  # 出ていろ
        ("キッチン行ってもろて", ["キッチン"]),  # 関西
        ("トイレ行ってちょう", ["トイレ"]),  # 名古屋
        ("お風呂場まで行っておくれやす", ["風呂"]),  # 京都
        ("まっすぐ玄関に行っとけ", ["玄関"]),
        ("広場まで移動お願いできますでしょうか", ["広場"]),  # でしょうか asks politely: no guess
        ("ろうかまでいってみて！", ["廊下"]),  # いって after まで is 行って, not 言って
        ("申し訳ないんですけど、キッチンまで移動お願いできますか？", ["キッチン"]),  # an apology opening it
        ("ご面倒をおかけしますが、洗面所へお願いいたします", ["洗面所"]),
        ("ほんまにゆっくり寝室行ってくれへん？", ["寝室"]),  # an intensifier
        ("私、リビング、行ってほしい", ["リビング"]),  # the speaker as the topic (not 私の: whose room)
        ("パパが帰ってくるから玄関行って", ["玄関"]),  # someone else comes home: their motion, a reason
        ("ねえねえロボットくん玄関行ってパパ帰ってきたよ", ["玄関"]),
        ("お客さん来たよ玄関行って", ["玄関"]),  # a sentence-final よ is a pause
        ("差し支えなければ、風呂に最も近い寝室へ移動していただけますでしょうか。", ["寝室"]),  # keigo
        ("キッチンには立ち寄らず、直接ダイニングへお願いします。", ["ダイニング"]),  # 直接: as まっすぐ
        ("ちゃうちゃう、リビングやって", ["リビング"]),  # a copula with emphasis
        ("トイレから一番遠い寝室がいいな", ["寝室"]),  # Xがいい: X is what is wanted
        ("玄関、いや、やっぱりリビングのほうがいいや", ["リビング"]),
        ("リビングにお願いしまーす", ["リビング"]),
        ("宅配来るっぽいから玄関行っといて", ["玄関"]),
        ("ゆっくりお風呂まで行ってください、床が濡れているので。", ["風呂"]),
        ("お腹すいた。キッチンに連れてって", ["キッチン"]),
    ],
)
def test_japanese_verb_endings_and_talk(text, visit):
    """Endings of a verb with no navigation meaning are read as its plain te-form; a reason or a statement around
    the instruction is passed over (spcotmhp/language/talk_ja.py)."""
    assert [p.words[0] for p in read(text, JA, "ja").visit] == visit


@pytest.mark.parametrize("text", ["帰ってきてから玄関行って", "キッチン行ってから帰って", "お客さん来た玄関行って"])
def test_the_robot_s_own_coming_back_and_a_relative_clause_stay_refused(text):
    with pytest.raises(InstructionError):
        read(text, JA, "ja")


@pytest.mark.parametrize(
    "text",
    [
        "トイレ通らんと玄関行って",
        "トイレ通らんで玄関行って",
        "トイレには入ったらあかんで、玄関行って",
        "トイレ通ったらだめ、玄関行って",
    ],
)
def test_western_negative_te_forms_and_must_not_avoid(text):
    """関西・西日本 〜んと / 〜んで and 〜たらあかん (must not): the place is avoided (ja.json talk.dialect)."""
    r = read(text, JA, "ja")
    assert [p.words[0] for p in r.visit] == ["玄関"] and [p.words[0] for p in r.avoid] == ["トイレ"]


def test_japanese_negated_endings_avoid_and_waivers_stay_refused():
    r = read("キッチンには入らんといてな、リビング行って", JA, "ja")
    assert [p.words[0] for p in r.visit] == ["リビング"] and [p.words[0] for p in r.avoid] == ["キッチン"]
    for waiver in ("トイレに寄らなくていいから風呂に行って", "廊下は通らなくてもいいので寝室へ"):
        with pytest.raises(UnsupportedPhrase, match="need not be done"):
            read(waiver, JA, "ja")


@pytest.mark.parametrize(
    "text",
    ["リビングに行ってテレビをつけて。", "キッチンに行ってお茶を取ってきてくれる？", "寝室に行ってコップ持ってきて"],
)
def test_japanese_requests_for_actions_are_not_talk(text):
    with pytest.raises(InstructionError):
        read(text, JA, "ja")


@pytest.mark.parametrize(
    "text, goal, via",
    [
        ("Go to the bedroom nearest the bath, no wait, nearest the toilet", "bedroom (closest to the toilet)", []),
        (
            "go to the bedroom closest to the bath oops i meant closest to the toilet",
            "bedroom (closest to the toilet)",
            [],
        ),
        ("go to the living room uh make that the dining room sorry", "dining room", []),  # a last apology
        ("go to the bedroom through the kitchen, er, through the hall I mean", "bedroom", ["hall"]),  # said after
    ],
)
def test_corrections_said_in_other_shapes(text, goal, via):
    """rewrite_en: a relation said alone after a correction, correction words side by side, one said last."""
    r = read(text, EN, "en")
    assert r.visit[-1].describe() == goal and [p.label for p in r.visit[:-1]] == via
    assert any("instead of" in h for h in r.heard), r.heard


def test_a_last_correction_word_with_nothing_to_mark_stays_refused():
    with pytest.raises(InstructionError):
        read("go to the kitchen sorry", EN, "en")


def test_a_place_referred_back_to_keeps_the_location_of_the_talk():
    """ "there" after a statement's location may be that location: the statement is not passed over."""
    for text in ("go to the kitchen, dad's in the garage, go there", "dad's in the garage. wait there"):
        with pytest.raises(InstructionError):
            read(text, EN, "en")
    r = read("Slowly to the lounge please, Grandad's asleep on the couch.", EN, "en")
    assert [p.words[0] for p in r.visit] == ["living"] and r.speed == "slow"
    assert any("grandad's asleep on couch" in h for h in r.heard), r.heard  # the article is a filler
