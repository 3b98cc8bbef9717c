"""Issue 34, session 12: a statement that names a place (rule 3c of spcotmhp/language/asides_en.py) and fillers
inside a Japanese noun (spcotmhp/language/lexicon_ja.py), read as meant or refused, never misread."""

from __future__ import annotations

import pytest

from spcotmhp.errors import InstructionError
from spcotmhp.language.reading import read
from tests.helpers.vocabulary import PLACE_WORDS_EN, PLACE_WORDS_JA


def _plan(text: str, lang: str = "en") -> tuple[list[str], list[str], str]:
    r = read(text, PLACE_WORDS_EN if lang == "en" else PLACE_WORDS_JA, lang)
    return [p.words[0] for p in r.visit], sorted(p.words[0] for p in r.avoid), r.speed or ""


@pytest.mark.parametrize(
    "text, visit",
    [
        ("Robot, I'm mopping the kitchen, go to the hall.", ["hall"]),
        ("could you go over to the hall please i'm vacuuming the corridor", ["hall"]),  # no pause before it
        ("I'm changing a dressing in the bedroom, so could you go to the dining room, love?", ["dining"]),
        ("Into the corridor please, the cleaner needs the dining room.", ["corridor"]),
        ("Would you mind moving into the corridor? We're hoovering the lounge.", ["corridor"]),
        ("I'm after mopping the kitchen so go to the living room", ["living"]),  # Irish "I'm after" = just did
        ("go to the kitchen, we're in the bath", ["kitchen"]),  # where people are: "Gran's napping in the lounge"
    ],
)
def test_a_place_in_a_statement_of_someone_else_is_neither_avoided_nor_gone_to(text, visit):
    assert _plan(text) == (visit, [], "")


@pytest.mark.parametrize(
    "text, visit, avoid",
    [
        ("The dog made a mess in the corridor, so avoid it and go to the kitchen.", ["kitchen"], ["corridor"]),
        ("Go to the bedroom. The kitchen is being cleaned, so don't go in there.", ["bedroom"], ["kitchen"]),
        ("The living room's a mess, so steer clear of it and head to the dining room.", ["dining"], ["living"]),
        ("I left my phone in the kitchen, go there please", ["kitchen"], []),
    ],
)
def test_it_or_there_after_a_statement_is_its_place(text, visit, avoid):
    assert _plan(text)[:2] == (visit, avoid)


@pytest.mark.parametrize(
    "text",
    [
        "i'm mopping the kitchen and the hall",  # a statement and nothing asked
        "The kids are playing in the living room, go join them.",  # the rest names no place
        "I'm cooking in the kitchen and bob's in the hall, go there",  # "there": which of the two?
        "the kitchen is wet, go to the hall and avoid it and there",  # two references back
    ],
)
def test_a_statement_with_a_place_and_no_instruction_of_its_own_is_refused(text):
    with pytest.raises(InstructionError):
        read(text, PLACE_WORDS_EN, "en")


def test_a_statement_ends_where_an_instruction_opens_not_inside_its_verb():
    """'... bath is running': "running" is the statement's verb, not the robot's speed (refused, never fast)."""
    try:
        r = read("Right, could you make your way to the bath now? Mr Doherty's bath is running.", PLACE_WORDS_EN, "en")
    except InstructionError:
        return
    assert [p.words[0] for p in r.visit] == ["bath"] and r.speed != "fast"


@pytest.mark.parametrize(
    "text, word",
    [("おかあさんが キッチンいってって", "おかあさん"), ("お父さんの寝室に行って", "お父さん")],
)
def test_a_filler_inside_a_noun_janome_knows_stays_the_nouns(text, word):
    """あ of おかあさん and さん of お父さん are characters of the noun: a refusal names the noun whole."""
    with pytest.raises(InstructionError, match=word):
        read(text, PLACE_WORDS_JA, "ja")


def test_a_filler_where_janome_runs_a_noun_into_a_place_word_is_still_left_out():
    """まあ その ものおき: janome reads そのもの; the place word ものおき wins and その is a filler."""
    assert _plan("まあ その ものおきにいってほしい", "ja")[0] == ["物置き"]


@pytest.mark.parametrize(
    "text, visit",
    [
        ("Go to the kitchen please, you're blocking the hall", ["kitchen"]),  # where the robot stands
        ("robot go into the loo please you're blocking the corridor", ["toilet"]),
        ("Go into the powder room.", ["toilet"]),  # the toilet only, never the washroom
        ("go to bed room number to", ["bedroom"]),  # a recogniser's "to" after "number"
        ("Go to the hall. Sorry, not the hall, the family room.", ["living"]),
        ("kitchen no sorry not the kitchen the dining room", ["dining"]),
    ],
)
def test_wave11_first_sight_refusals_and_misreadings_read_as_meant(text, visit):
    assert _plan(text)[0] == visit


def test_number_to_after_number_is_two_and_to_elsewhere_stays_to():
    r = read("go to bed room number to", PLACE_WORDS_EN, "en")
    assert r.visit[-1].number == 2
    r = read("go to the bedroom to the kitchen", PLACE_WORDS_EN, "en")
    assert [p.number for p in r.visit] == [None, None]


def test_a_place_said_again_as_where_to_go_is_one_visit():
    r = read("ダイニングに行って。キッチンじゃないよ、ダイニング。", PLACE_WORDS_JA, "ja")
    assert [p.words[0] for p in r.visit] == ["ダイニング"] and [p.words[0] for p in r.not_goal] == ["キッチン"]
    assert any("said again" in h for h in r.heard)
    r = read("wait in the kitchen for 2 minutes then go to the kitchen", PLACE_WORDS_EN, "en")
    assert len(r.visit) == 2 and r.waits == ((0, 120.0),)  # a wait at the first saying keeps both


def test_after_the_robot_has_done_something_at_a_place_it_visits_it():
    """ "after you've checked the toilet" (blind): the robot's past action at a place makes it a waypoint; only a
    present -ing ("you're blocking the hall") says where it stands."""
    assert _plan("after you've checked the toilet go to the bedroom")[0] == ["toilet", "bedroom"]


@pytest.mark.parametrize(
    "text, goal",
    [
        ("今会議中だから、ダイニングに行ってて。", "ダイニング"),  # the meeting is now: the statement's time
        ("ごめん手が離せない、物置き行っといて。", "物置き"),  # the speaker cannot: the statement's negation
        ("歯磨きの時間だから洗面所に行っといて。", "洗面所"),  # time for: no length
        ("ご飯もうすぐできるよ、ダイニング行ってて", "ダイニング"),  # で of できる is no particle
    ],
)
def test_a_japanese_statement_keeps_its_own_time_and_negation(text, goal):
    assert _plan(text, "ja")[0] == [goal]


@pytest.mark.parametrize("text", ["今行くから、ダイニングに行ってて", "入らないから、キッチンに行って"])
def test_time_or_negation_with_a_verb_of_going_keeps_the_clause(text):
    """With a verb of the table the time or negation may be the robot's: the clause stays (read or refused)."""
    try:
        r = read(text, PLACE_WORDS_JA, "ja")
    except InstructionError:
        return
    assert not any("今行く" in h or "入らない" in h for h in r.heard), r.heard


@pytest.mark.parametrize(
    "text, visit, wait",
    [
        ("リビングの方へいらして。", ["リビング"], ()),  # いらっしゃる: the honorific of 行く / 来る
        ("食堂へお行きになって。", ["ダイニング"], ()),
        ("ロボットさん、キッチンを行ってください。", ["キッチン"], ()),  # を 行く: along it, to it (learners)
        ("廊下を行って玄関まで", ["廊下", "玄関"], ()),  # along the corridor, then to the entrance
        ("ロウカ に いって ください", ["廊下"], ()),  # a place word's sound in katakana
        ("ひろばで10びょうまってて", ["広場"], ((0, 10.0),)),  # a length in kana
        ("半時間ばかり風呂場で待っててくんな", ["風呂"], ((0, 1800.0),)),  # ばかり: about
    ],
)
def test_wave11_japanese_forms(text, visit, wait):
    r = read(text, PLACE_WORDS_JA, "ja")
    assert [p.words[0] for p in r.visit] == visit and r.waits == wait


def test_back_and_forth_stays_refused():
    """行ったり来たり (back and forth) is no plain 行って: its たり keeps it as said, and it is refused."""
    with pytest.raises(InstructionError):
        read("キッチンとお風呂を行ったり来たりして", PLACE_WORDS_JA, "ja")


def test_a_katakana_reading_of_two_kana_is_no_place_word():
    """フロ (風呂) is no spelling: it is the start of フロア (a floor)."""
    from spcotmhp.language.lexicon import tokens
    from spcotmhp.language.table import word_table

    toks = tokens("フロアに行って", word_table("ja"), PLACE_WORDS_JA)
    assert not any(t.kind == "PLACE" for t in toks)


def test_a_place_allowed_again_after_its_avoidance_is_no_waypoint():
    """リビング避けて、いや、リビング通ってもいいや: passing is allowed, not asked (blind50)."""
    r = read("リビングを避けて、いや、リビング通ってもいいや、キッチンまで", PLACE_WORDS_JA, "ja")
    assert [p.words[0] for p in r.visit] == ["キッチン"] and r.avoid == ()


def test_going_to_x_instead_is_not_ending_there():
    """お風呂に行くんじゃなくて、脱衣所で: X じゃなくて with its verb, a place not to end in (blind51)."""
    r = read("お風呂に行くんじゃなくて、脱衣所でお願いします。", PLACE_WORDS_JA, "ja")
    assert [p.words[0] for p in r.not_goal] == ["風呂"] and r.avoid == ()


@pytest.mark.parametrize(
    "text, goal, visits",
    [
        ("Go to the bedroom nearest the laundry. The laundry. Nearest the laundry.", "bedroom", 1),
        ("Go to the kitchen. The kitchen!", "kitchen", 1),
        ("Go to the kitchen. The hall.", "hall", 2),  # a new place is no echo
    ],
)
def test_a_sentence_that_only_says_again_what_was_said_adds_nothing(text, goal, visits):
    r = read(text, PLACE_WORDS_EN, "en")
    assert r.visit[-1].words[0] == goal and len(r.visit) == visits


@pytest.mark.parametrize(
    "text, visit, avoid",
    [
        ("Go to the toilet, then the bathroom.", ["toilet", "bath"], []),  # the toilet named: the bathroom is the bath
        ("Don't go in the bathroom. Go to the toilet.", ["toilet"], ["bath"]),
        ("keep out of the toilet and the bathroom and go to the storeroom", ["storeroom"], ["bath", "toilet"]),
        ("the bathroom with the washing machine", ["washroom"], []),  # the thing tells the room
        ("go to the bathroom where the toilet is", ["toilet"], []),  # the toilet as what is in it: no contrast
    ],
)
def test_bathroom_beside_the_toilet_named_is_the_bath(text, visit, avoid):
    assert _plan(text)[:2] == (visit, avoid)


@pytest.mark.parametrize(
    "text",
    [
        "go to the bathroom",
        "I'm gonna take a bath, go to the bathroom",
        "Make your way to the bathroom please",
        "go to the loo, the bathroom",  # said beside it: maybe another name of the same room
        "go to the toilet, I mean the bathroom",  # a correction: a politer name of the room, or another room
        "go to the bathroom and use the toilet",  # the room whose toilet is used
    ],
)
def test_bathroom_alone_or_beside_the_bath_as_an_activity_stays_refused(text):
    """The bath or the toilet: writers split on the bare word (55 the bath, 27 refused, the frozen held-out among
    them); "a bath" names what is done as well as the room, and rules nothing out."""
    with pytest.raises(InstructionError, match="say which"):
        read(text, PLACE_WORDS_EN, "en")


def test_hang_out_is_a_wait():
    r = read("go to the hall and hang out there for ten minutes", PLACE_WORDS_EN, "en")
    assert [p.words[0] for p in r.visit] == ["hall"] and r.waits == ((0, 600.0),)


@pytest.mark.parametrize(
    "text, visit",
    [
        ("おばあちゃんがね、風呂場に行ってって言ってたよ", ["風呂"]),  # a request relayed: granny said go
        ("広場へ行けと言っとる、広場だ。", ["広場"]),  # "I'm telling you": the request said again
        ("キッチン通ってって言ったけど、やっぱりダイニング通ってリビングに行って", ["ダイニング", "リビング"]),
    ],
)
def test_a_request_said_with_its_saying_is_the_request(text, visit):
    assert _plan(text, "ja")[0] == visit


def test_a_quote_of_no_request_stays_as_said():
    from spcotmhp.language.talk_ja import relayed

    assert relayed("キッチンが広いって言ってた") == "キッチンが広いって言ってた"  # no te-form or imperative quoted


@pytest.mark.parametrize(
    "text, goal",
    [("go along the corridor please", "corridor"), ("would you head down the corridor", "corridor")],
)
def test_a_place_gone_along_alone_is_where_to_go(text, goal):
    assert _plan(text)[0] == [goal]


@pytest.mark.parametrize("text", ["go through the kitchen", "head down the hallway"])
def test_through_alone_or_along_a_word_of_two_senses_stays_refused(text):
    with pytest.raises(InstructionError):
        read(text, PLACE_WORDS_EN, "en")


@pytest.mark.parametrize(
    "text, goal, visits",
    [
        ("go to the bedroom, nearest the kitchen", "bedroom", 1),  # the relation after a pause picks the bedroom
        ("goto bedroom --nearest kitchen", "bedroom", 1),
        ("Which bedroom? The one nearest the storeroom. Go there.", "bedroom", 1),  # the question is no visit
        ("Robot please go to the hallway so the aide can get the wheelchair through the living room.", "corridor", 1),
    ],
)
def test_wave13_misreadings_read_as_meant(text, goal, visits):
    r = read(text, PLACE_WORDS_EN, "en")
    assert r.visit[-1].words[0] == goal and len(r.visit) == visits
    if "nearest" in text:
        assert r.visit[-1].relation is not None


def test_wait_then_a_correction_is_one_correction_not_a_wait():
    r = read("Go to the kitchen avoiding the hall, wait, I meant avoiding the hallway.", PLACE_WORDS_EN, "en")
    assert r.waits == () and [p.words[0] for p in r.avoid] == ["corridor"]


def test_a_third_persons_motion_stays_theirs_only_before_its_place():
    """ "the babysitter needs the kitchen free go to the corridor": the robot's "go" is no motion of the
    babysitter's statement."""
    r = read("hey so the babysitter needs the kitchen free go to the corridor", PLACE_WORDS_EN, "en")
    assert [p.words[0] for p in r.visit] == ["corridor"]


@pytest.mark.parametrize(
    "text, visit, avoid, speed",
    [
        ("nav kitchen via hall", ["hall", "kitchen"], [], None),  # "nav": navigate, as a terminal user types it
        ("nav bath --avoid kitchen --slow", ["bath"], ["kitchen"], "slow"),
        ("Robot, go inna di kitchen nuh.", ["kitchen"], [], None),  # Jamaican Creole: into the kitchen
        ("Go to the hall. Wait, not the hall, the corridor.", ["corridor"], [], None),  # "wait," a correction
    ],
)
def test_wave13_forms(text, visit, avoid, speed):
    r = read(text, PLACE_WORDS_EN, "en")
    assert [p.words[0] for p in r.visit] == visit and [p.words[0] for p in r.avoid] == avoid and r.speed == speed


@pytest.mark.parametrize(
    "text, goal",
    [
        ("ロボットはん、広場まで行っとくれやす", "広場"),  # 京都: 〜とくれやす, はん
        ("納戸まで行っとくれ、おおきに", "物置き"),  # 京都: 〜とくれ; おおきに thanks
        ("おう、ロボ公、玄関先まで行ってくんな。", "玄関"),  # 下町: 〜てくんな, ロボ公
    ],
)
def test_kyoto_and_shitamachi_endings(text, goal):
    assert _plan(text, "ja")[0] == [goal]


@pytest.mark.parametrize(
    "text, goal",
    [
        ("Pick the bedroom closest to the hall and go there.", "bedroom"),
        ("Pick whichever bedroom is nearest the dining room", "bedroom"),
        ("choose the kitchen", "kitchen"),
    ],
)
def test_a_verb_of_choosing_before_a_place_is_going_there(text, goal):
    assert _plan(text)[0] == [goal]


def test_pick_up_stays_refused():
    with pytest.raises(InstructionError):
        read("pick up the towel in the bath", PLACE_WORDS_EN, "en")


def test_slowly_will_do_with_a_reasons_shi_is_slow():
    assert _plan("ゆっくりでいいし、物置きまで行って", "ja") == (["物置き"], [], "slow")


@pytest.mark.parametrize("text", ["りびんぐ… えっとね… きっちん！", "キッチン あの えっと リビング"])
def test_a_hesitation_between_two_bare_places_is_refused_not_read_as_a_way(text):
    """Whether the second place replaces the first or follows it is a guess (as "the kitchen... uh... the dining
    room" is refused in English): refused naming the hesitation (blind59 had read it as a waypoint)."""
    with pytest.raises(InstructionError, match="hesitation"):
        read(text, PLACE_WORDS_JA, "ja")


def test_the_same_place_after_a_filler_is_no_hesitation():
    assert _plan("洗面所じゃなくて風呂ね風呂場", "ja")[0] == ["風呂"]


def test_i_beg_your_pardon_corrects():
    assert _plan("Make your way to the kitchen - I beg your pardon, the dining room.")[0] == ["dining"]


@pytest.mark.parametrize(
    "text",
    [
        "寝室に行けって言ってない",  # a saying denied, forbidden, wished or asked for stays as said
        "トイレに行ってって言わないで",
        "風呂に行ってって言うな",
        "寝室に行けって言っといて",
        "リビングに行けなんて言ってない、キッチンに行って",
    ],
)
def test_a_saying_denied_or_asked_for_is_no_request(text):
    with pytest.raises(InstructionError):
        read(text, PLACE_WORDS_JA, "ja")


def test_i_was_told_x_but_y_corrects_x():
    assert _plan("キッチンに行けって言ってたけど、寝室に行って", "ja")[0] == ["寝室"]
    assert _plan("リビングに行けって言われたけど、キッチンに行って", "ja")[0] == ["キッチン"]


@pytest.mark.parametrize(
    "text, visit",
    [
        ("Go to the kitchen. Go to the hall. Go to the kitchen.", ["kitchen", "hall", "kitchen"]),  # no echo
        ("go to the kitchen, the nearest bedroom", ["kitchen", "bedroom"]),  # "the nearest X": a place of its own
    ],
)
def test_reviewed_sentences_keep_their_places(text, visit):
    assert _plan(text)[0] == visit


@pytest.mark.parametrize(
    "text",
    [
        "the kitchen is forbidden, go to the hall",  # passability
        "go to the hall, the corridor is quicker",  # a way through advised
        "you're vacuuming the hall later, go to the kitchen now",  # the robot's time
        "Tonight. Robot, go to the kitchen.",  # a time before the robot's name may be the robot's
        "the kids are asleep in bedroom 1 and bedroom 2, so stay out of there and go to the kitchen",
    ],
)
def test_reviewed_sentences_are_refused(text):
    with pytest.raises(InstructionError):
        read(text, PLACE_WORDS_EN, "en")
