"""Japanese as people say it, wave 4 (issue 34; spcotmhp/language/spoken_ja.py and the ja.json data it reads):
rooms told by their contents, the master bedroom, requests said as thanks, waits said after or corrected, until
told, everyday words. Each rule has cases it reads and cases that must stay refused."""

from __future__ import annotations

import pytest

from spcotmhp.errors import InstructionError
from spcotmhp.language.meaning import Reading
from spcotmhp.language.reading import read
from tests.helpers.vocabulary import PLACE_WORDS_JA

JA = PLACE_WORDS_JA


def _visit(r: Reading) -> list[str]:
    return [p.words[0] + (f"#{p.number}" if p.number else "") for p in r.visit]


@pytest.mark.parametrize(
    "text, goal",
    [
        ("洗濯機のとこ行って", "洗面所"),
        ("洗濯機のある部屋まで行って", "洗面所"),
        ("冷蔵庫の前まで行っといて", "キッチン"),
        ("冷蔵庫のとこまで行ってて", "キッチン"),
        ("ソファのとこ行ってて", "リビング"),
        ("テレビの部屋に行ってて", "リビング"),
        ("ダイニングテーブルのとこ行って", "ダイニング"),
    ],
)
def test_a_room_told_by_its_contents(text, goal):
    assert _visit(read(text, JA, "ja"))[-1] == goal


@pytest.mark.parametrize(
    "text",
    [
        "流しのとこ行って",  # a sink is in the kitchen and in the washroom: which?
        "テレビをつけて",  # a thing with no word for its place is no place
    ],
)
def test_contents_held_by_several_rooms_or_no_place_stay_refused(text):
    with pytest.raises(InstructionError):
        read(text, JA, "ja")


def test_contents_need_the_room_in_the_map():
    with pytest.raises(InstructionError):
        read("洗濯機のとこ行って", [w for w in JA if w != "洗面所"], "ja")


def test_the_master_bedroom_is_the_largest():
    r = read("主寝室に行ってちょうだい", JA, "ja")
    assert r.visit[-1].relation is not None and r.visit[-1].relation.kind == "largest"


@pytest.mark.parametrize(
    "text, goal",
    [
        ("リビングに行ってくれたら助かるんだけど", "リビング"),
        ("洗面所いってくれたら嬉しい", "洗面所"),
        ("あのですね、キッチンのほうにちょっと行ってもらえたら助かるんですけど", "キッチン"),
    ],
)
def test_a_favour_that_would_help_is_a_request(text, goal):
    assert _visit(read(text, JA, "ja")) == [goal]


@pytest.mark.parametrize(
    "text", ["雨降ってたら洗面所に行って", "キッチンに行ったらリビングが助かる?", "6時になったらリビングに行って"]
)
def test_any_other_condition_stays_refused(text):
    with pytest.raises(InstructionError):
        read(text, JA, "ja")


@pytest.mark.parametrize(
    "text, waits",
    [
        ("リビングで待っててくれる？15分ぐらい", ((0, 900.0),)),
        ("お風呂に行って10分そこで待ってて", ((0, 600.0),)),
        ("トイレで5分待って、いや10分", ((0, 600.0),)),
        ("ダイニングで5分待って いや10分で その後キッチン", ((0, 600.0),)),
        ("リビングに1時間いてそれからキッチン", ((0, 3600.0),)),
        ("お風呂行く途中で洗面所に3分いてね", ((0, 180.0),)),
        ("90秒だけダイニングで待ってからキッチン", ((0, 90.0),)),
        ("半時間ほど洗面所で待っとって", ((0, 1800.0),)),
    ],
)
def test_lengths_said_after_before_there_or_corrected(text, waits):
    assert read(text, JA, "ja").waits == waits


@pytest.mark.parametrize(
    "text",
    [
        "お風呂場に行って、呼ぶまでそこにいて",
        "物置きまで行って、そこで次の指示まで待機",
        "キッチンで待っとって、呼ぶまで",
        "わしが呼ぶまで玄関で待っとれ",
        "リビングでしばらく待機してて",
    ],
)
def test_a_wait_until_told_lasts_until_the_next_instruction(text):
    assert read(text, JA, "ja").waits == ((0, None),)


@pytest.mark.parametrize("text", ["呼ぶまでキッチンに行って", "玄関で2時間待っててね"])
def test_until_told_with_no_wait_and_a_wait_too_long_stay_refused(text):
    with pytest.raises(InstructionError):
        read(text, JA, "ja")


@pytest.mark.parametrize(
    "text, visit",
    [
        ("キッチン行ってちょー", ["キッチン"]),
        ("おーい、キッチンまで", ["キッチン"]),
        ("ねぇ、廊下まで出てくれる？", ["廊下"]),
        ("悪いけど洗面所まで行ってくれない？", ["洗面所"]),
        ("目的地：リビング", ["リビング"]),
        ("行き先はトイレで", ["トイレ"]),
        ("じゃあ次はリビング", ["リビング"]),
        ("倉庫部屋に行って", ["物置き"]),
        ("ちょっとかわやへ行ってくれ", ["トイレ"]),
        ("廊下→広場→リビングの順で行って", ["廊下", "広場", "リビング"]),
        ("途中でキッチン通って最後リビングで止まって", ["キッチン", "リビング"]),
        ("洗面所まで、ってかお風呂までお願い", ["風呂"]),
        ("物置きに…って違う違う、玄関！", ["玄関"]),
        ("トイレ行ってあーやっぱなしリビングにして", ["リビング"]),
        ("寝室#1、ごめん#3だった", ["寝室#3"]),
        ("トイレに行って…いや、やっぱり洗面所で", ["洗面所"]),
        ("玄関で待ってて、やっぱ取り消し、廊下で待ってて", ["廊下"]),
    ],
)
def test_everyday_words_orders_and_corrections(text, visit):
    assert _visit(read(text, JA, "ja")) == visit


@pytest.mark.parametrize(
    "text, speed",
    [
        ("早足でダイニングまで行ってくれるかい", "fast"),
        ("トイレ、なるはやで", "fast"),
        ("洗面所まで、走らないでゆっくりね", "slow"),
    ],
)
def test_speed_words(text, speed):
    assert read(text, JA, "ja").speed == speed


def test_right_next_to_is_next_to():
    r = read("洗面所のすぐ隣の寝室行って", JA, "ja")
    assert r.visit[-1].relation is not None and r.visit[-1].relation.kind == "next_to"


def test_never_entering_is_avoiding():
    r = read("台所には絶対入らないでね、リビングに行って", JA, "ja")
    assert _visit(r) == ["リビング"] and [a.words[0] for a in r.avoid] == ["キッチン"]


@pytest.mark.parametrize(
    "text, quoted",
    [
        ("窓のある寝室に行って", "'窓のある'"),
        ("10分後にキッチンへ", "'10分後に'"),
        ("玄関で2時間待っててね", "'2時間'"),
        ("6時になったらリビングに行って", "'6時になったら'"),
        ("雨降ってたら洗面所に行って", "'雨降ってたら'"),
        ("リビング行って帰ってきて", "帰ってきて"),
        ("もし雨が降ってたら玄関に行って", "'もし'"),
    ],
)
def test_a_refusal_quotes_the_whole_phrase(text, quoted):
    with pytest.raises(InstructionError) as info:
        read(text, JA, "ja")
    assert quoted in str(info.value)


@pytest.mark.parametrize(
    "text, visit",
    [
        ("バスルーム行って", ["風呂"]),  # senses: the bath first where the map has a bath
        ("茶の間さ行げ", ["リビング"]),  # 東北: 行げ is 行け
        ("風呂場さ行ってけれ", ["風呂"]),
        ("リビングに…あ、ごめん、寝室やった", ["寝室"]),  # a past copula after a correction
        ("寝室1番、いや2番だった", ["寝室#2"]),  # a pause before the correction
        ("ダイニング、あ、ちがいます、キッチン、ください", ["キッチン"]),
        ("ほな台所行っといて", ["キッチン"]),
    ],
)
def test_senses_dialect_and_corrections(text, visit):
    assert _visit(read(text, JA, "ja")) == visit


def test_bathroom_without_a_bath_is_the_next_sense():
    assert _visit(read("バスルーム行って", [w for w in JA if w != "風呂"], "ja")) == ["洗面所"]


@pytest.mark.parametrize(
    "text, waits",
    [("玄関で5分待って、いや3分でいい", ((0, 180.0),)), ("物置きで5分、じゃなくて10分待って", ((0, 600.0),))],
)
def test_a_length_corrected_in_other_words(text, waits):
    assert read(text, JA, "ja").waits == waits


@pytest.mark.parametrize("text", ["急ぎで頼む、玄関に行ってくれ、リビングは通るなよ", "玄関に行って、リビングは通るな"])
def test_the_dictionary_form_and_na_forbid(text):
    r = read(text, JA, "ja")
    assert not r.visit[:-1] and [a.words[0] for a in r.avoid] == ["リビング"]


def test_mo_marks_a_place_avoided_as_the_one_before():
    r = read("トイレには入らないで、お風呂にも入らないで、寝室に行って", JA, "ja")
    assert sorted(a.words[0] for a in r.avoid) == ["トイレ", "風呂"]


@pytest.mark.parametrize(
    "text, visit, not_goal",
    [
        ("ダイニングね、キッチンじゃなくて", ["ダイニング"], ["キッチン"]),  # ね、closes the bare place
        ("寝室に行って、えっと、取り消し、リビングにして", ["リビング"], []),  # a cancel between two places
        ("おつかれ～、リビングに戻っといて", ["リビング"], []),
    ],
)
def test_closing_particles_pauses_and_cancels(text, visit, not_goal):
    r = read(text, JA, "ja")
    assert _visit(r) == visit and [p.words[0] for p in r.not_goal] == not_goal


def test_staying_at_a_place_is_a_wait_until_told():
    assert read("廊下でおってくれへん？", JA, "ja").waits == ((0, None),)


@pytest.mark.parametrize("text", ["リビングに行って、やっぱり取り消し", "取り消し、リビング"])
def test_a_cancel_with_no_place_on_one_side_stays_refused(text):
    with pytest.raises(InstructionError):
        read(text, JA, "ja")


@pytest.mark.parametrize(
    "text, visit, speed",
    [
        ("キッチン（訂正）ダイニング", ["ダイニング"], None),  # a bracketed aside is a pause
        ("廊下、広場の順に通ってキッチンまで", ["廊下", "広場", "キッチン"], None),
        ("洗面所、トイレの順に寄ってリビングまで", ["洗面所", "トイレ", "リビング"], None),
        ("納戸に入っといて", ["物置き"], None),
        ("ダイニングまで急いで、あーいいや、ゆっくりで", ["ダイニング"], "slow"),
        ("広場でいいので行ってください", ["広場"], None),
        ("寝室ならどこでもいいので行ってください", ["寝室"], None),
        ("えっとどこでもいいから寝室 寝室に行って", ["寝室"], None),
    ],
)
def test_orders_anywhere_and_will_do(text, visit, speed):
    r = read(text, JA, "ja")
    assert _visit(r) == visit and r.speed == speed


@pytest.mark.parametrize("text", ["の順に通ってキッチンまで", "どこでもいいから"])
def test_an_order_or_anywhere_with_nothing_to_go_with_stays_refused(text):
    with pytest.raises(InstructionError):
        read(text, JA, "ja")


@pytest.mark.parametrize(
    "text, visit",
    [
        ("キッチン通ってリビングに、いや、キッチンは通らないで", ["リビング"]),
        ("キッチン通って、あ、違う、キッチンは通らないで寝室", ["寝室"]),
    ],
)
def test_a_place_corrected_to_another_role(text, visit):
    r = read(text, JA, "ja")
    assert _visit(r) == visit and [a.words[0] for a in r.avoid] == ["キッチン"]
    assert any("said instead of" in h for h in r.heard)


@pytest.mark.parametrize("text", ["お風呂沸いたよ、風呂場のほうに行ってて", "お風呂沸いたって。お風呂行っといて"])
def test_a_statement_about_a_place_said_again_is_talk(text):
    r = read(text, JA, "ja")
    assert _visit(r) == ["風呂"] and any("passed over" in h for h in r.heard)


def test_a_statement_about_a_place_not_said_again_stays_refused():
    with pytest.raises(InstructionError):
        read("キッチン汚れてるから、リビング行って", JA, "ja")


def test_a_statement_about_a_marked_place_said_again_is_talk():
    assert _visit(read("玄関にお客さん来るから玄関まで行っておいて", JA, "ja")) == ["玄関"]


@pytest.mark.parametrize(
    "text, visit", [("ご飯できたよ〜ダイニングおいで", ["ダイニング"]), ("洗面所お願いしま〜す", ["洗面所"])]
)
def test_a_wave_dash_before_a_word_is_a_pause_and_inside_one_a_drawn_out_sound(text, visit):
    assert _visit(read(text, JA, "ja")) == visit
