"""Japanese as people say it, session 7 of issue 34 (the ja.json data and spcotmhp/language/text.py): a size said
without 一番 (大きい寝室, 小さいほうの寝室, as English "the big bedroom"), 次 for "next", とりあえず as a hedge, 第N and
No.N as a screen number, pictographs and texting laughter passed over. Each with cases that must stay refused."""

from __future__ import annotations

import pytest

from spcotmhp.errors import InstructionError
from spcotmhp.language.meaning import Reading
from spcotmhp.language.reading import read
from spcotmhp.language.text import without_pictographs
from tests.helpers.vocabulary import PLACE_WORDS_JA

JA = PLACE_WORDS_JA


def _visit(r: Reading) -> list[str]:
    return [p.words[0] + (f"#{p.number}" if p.number else "") for p in r.visit]


@pytest.mark.parametrize(
    "text, size",
    [
        ("大きい寝室行ってて", "largest"),
        ("小さいほうの寝室へ", "smallest"),
        ("大きい方の寝室", "largest"),
        ("広い寝室で待ってて", "largest"),
        ("せまい寝室に行って", "smallest"),
    ],
)
def test_a_size_without_ichiban_picks_by_size(text, size):
    r = read(text, JA, "ja")
    assert len(r.visit) == 1 and r.visit[0].words[0] == "寝室" and r.visit[0].relation.kind == size


@pytest.mark.parametrize(
    "text, visit",
    [
        ("次物置き", ["物置き"]),
        ("ダイニング行って次キッチン", ["ダイニング", "キッチン"]),
        ("とりあえずリビングに行っといて", ["リビング"]),
        ("第3寝室へ移動してください", ["寝室#3"]),
        ("寝室No.1", ["寝室#1"]),
        ("玄関、よろしくね🙏", ["玄関"]),
        ("キッチン行ってもらえる？😊", ["キッチン"]),
        ("キッチン行っといてーw", ["キッチン"]),
        ("洗面所へ行って頂戴", ["洗面所"]),
        ("お風呂場へどうぞ", ["風呂"]),
        ("キッキッチン行って", ["キッチン"]),  # a place word begun and said again whole
    ],
)
def test_next_hedges_numbers_and_pictographs(text, visit):
    assert _visit(read(text, JA, "ja")) == visit


@pytest.mark.parametrize(
    "text, size",
    [
        ("寝室の一番大きいとこ", "largest"),  # the size after the place, とこ standing for it
        ("寝室のうちで一番広いとこへ", "largest"),
        ("寝室の、一番広いとこ", "largest"),
        ("寝室で一番大きいの", "largest"),
        ("ベッドルームの一番狭いところで待ってて", "smallest"),
    ],
)
def test_a_size_said_after_the_place(text, size):
    r = read(text, JA, "ja")
    assert r.visit[-1].words[0] == "寝室" and r.visit[-1].relation.kind == size


def test_a_while_is_until_told_and_early_is_fast():
    r = read("しばらく広場で待ってて", JA, "ja")
    assert r.waits == ((0, None),)
    assert read("ダイニングで2分待って、それから玄関まで早めに", JA, "ja").speed == "fast"


@pytest.mark.parametrize(
    "text",
    [
        "3番目の寝室に行って",  # an ordinal counts along something the map does not hold
        "次の寝室",  # "the next bedroom": next after what?
    ],
)
def test_what_stays_refused(text):
    with pytest.raises(InstructionError):
        read(text, JA, "ja")


def test_arrows_stay_and_pictographs_go():
    assert without_pictographs("風呂→寝室") == "風呂→寝室"
    assert without_pictographs("玄関🙏") == "玄関 " and without_pictographs("玄関👍🏽") == "玄関  "
    assert without_pictographs("トイレwc") == "トイレwc"  # a w that is part of a word stays


@pytest.mark.parametrize(
    "text, visit, waits",
    [
        ("リビングで5分待って。いや10分", ["リビング"], [600.0]),  # a correction after a full stop
        ("リビングで5分待って、いややっぱ10分", ["リビング"], [600.0]),  # two correction words, one correction
        ("キッチンで5分待って、あー10分にして", ["キッチン"], [600.0]),  # にして: make it ten minutes
        ("キッチンで5分待って、いや10分にして", ["キッチン"], [600.0]),
        ("キッチンで5分待って、トイレに行って", ["キッチン", "トイレ"], [300.0]),  # no correction: as said
        ("寝室で10分ほどお待ちいただけますか", ["寝室"], [600.0]),  # the honorific wait
        ("恐れ入ります、洗面所にて3分ほど待機された後、寝室＃３へお願いします。", ["洗面所", "寝室#3"], [180.0]),
    ],
)
def test_a_length_corrected_replaces_the_wait_s_length(text, visit, waits):
    """Session 8: a length said again after a correction, or with にして, is the wait's (spoken_ja)."""
    r = read(text, JA, "ja")
    assert _visit(r) == visit and [s for _, s in r.waits] == waits


@pytest.mark.parametrize(
    "text, visit",
    [
        ("寝室の1番ごめん2番", ["寝室#2"]),  # an apology between two numbers of one place corrects
        ("キッチンごめんリビング", ["リビング"]),  # between two places
        ("ごめんキッチン行って", ["キッチン"]),  # elsewhere a filler
        ("キッチン行ってごめん", ["キッチン"]),
        ("2番寝室に行って", ["寝室#2"]),  # a screen number before the place without の
        ("2番寝室へ行くください", ["寝室#2"]),
    ],
)
def test_apologies_between_places_correct_and_numbers_before_a_place(text, visit):
    assert _visit(read(text, JA, "ja")) == visit


def test_an_ordinal_before_a_place_stays_refused():
    with pytest.raises(InstructionError):
        read("3番目の寝室に行って", JA, "ja")


@pytest.mark.parametrize(
    "text, relation",
    [
        ("寝室、トイレに近いとこ", "closest"),  # a pause for の before the relation said after the place
        ("寝室、トイレに近いやつ。", "closest"),
        ("寝室に行って。キッチンから一番遠いやつね。", "farthest"),  # after the place's own sentence
        ("寝室の一番トイレに近いとこ", "closest"),  # 一番 before the relation's place is "most", no number
    ],
)
def test_a_relation_said_after_the_place_with_a_pro_form(text, relation):
    r = read(text, JA, "ja")
    assert len(r.visit) == 1 and r.visit[0].words[0] == "寝室" and r.visit[0].relation.kind == relation
    assert r.visit[0].number is None


def test_ichiban_alone_after_a_place_is_its_number():
    assert _visit(read("寝室の一番に行って", JA, "ja")) == ["寝室#1"]


@pytest.mark.parametrize(
    "text, visit, avoid",
    [
        ("トイレで待ってて、いや待たなくていいや", ["トイレ"], []),  # a wait taken back
        ("玄関で待っててあやっぱ待たなくていいや行くだけで", ["玄関"], []),  # and "just go"
        ("リビングで待機してて。あ、待機はいいや、行くだけで", ["リビング"], []),
        ("洗面所通ってお風呂、いや、やっぱ洗面所は通らなくていい", ["風呂"], []),  # a place to pass taken back
        ("廊下通ってキッチン、あーやっぱ廊下はいいや、そのままキッチン", ["キッチン"], []),
        ("リビング避けて…あ、やっぱり通っていいよ、ダイニングまで", ["ダイニング"], []),  # an avoidance taken back
        ("キッチンは避けて…あ、避けなくていいや、リビングに行って", ["リビング"], []),
    ],
)
def test_a_part_taken_back_is_left_out(text, visit, avoid):
    """Session 8 (withdrawals_ja): a correction replaces a wait, a place to pass or an avoidance with nothing."""
    r = read(text, JA, "ja")
    assert _visit(r) == visit and [p.words[0] for p in r.avoid] == avoid and not r.waits


@pytest.mark.parametrize(
    "text, reason",
    [
        ("キッチンに行って、待たなくていいや", "need not be done"),  # nothing to take back: a waiver
        ("トイレ行って、廊下はいいや", "not said as a place to pass"),
        ("キッチン通ってリビング、やっぱり通っていいよ", "no place to avoid"),
    ],
)
def test_a_withdrawal_with_nothing_to_take_back_is_refused(text, reason):
    with pytest.raises(InstructionError, match=reason):
        read(text, JA, "ja")


@pytest.mark.parametrize(
    "text, visit",
    [
        ("おはよう！キッチンまで行ってくれる？", ["キッチン"]),  # a greeting
        ("Hey ロボット 廊下 行って ください", ["廊下"]),
        ("広場を通って、ダイニングも通って、キッチンへゆっくりお願いします", ["広場", "ダイニング", "キッチン"]),  # も
        ("ダイニングに寄って、キッチンにも寄って、最後はリビングね", ["ダイニング", "キッチン", "リビング"]),
        ("リビングに行って。やっぱりやめた、キッチンに行って", ["キッチン"]),  # やめた: taken back
        ("物置きへお願いします、あら、ごめんなさい、玄関でしたわ", ["玄関"]),  # でした: it was X
        ("ダイニングに行ってください、すみません、リビングの間違いでした", ["リビング"]),  # Xの間違い: X was meant
        ("広場って所に行ってくれる？", ["広場"]),
    ],
)
def test_wave_7_forms(text, visit):
    """Session 8, from blind31 after its measurement."""
    assert _visit(read(text, JA, "ja")) == visit


@pytest.mark.parametrize("text", ["お風呂には入らないようにして洗面所に行ってね", "玄関 行く、でも 風呂 に 入る だめ"])
def test_wave_7_avoidances(text):
    r = read(text, JA, "ja")
    assert [p.words[0] for p in r.avoid] == ["風呂"]


@pytest.mark.parametrize(
    "text, visit, waits",
    [
        ("キッチンで ごふん まってて", ["キッチン"], [300.0]),  # a length in kana, as a recogniser writes it
        ("ろうかで いっぷん まってから げんかんいって", ["廊下", "玄関"], [60.0]),
        ("ふろで にじゅっぷん まっててや", ["風呂"], [1200.0]),
        ("げんかんいっといて", ["玄関"], []),  # いって after a place is 行って
        ("だいどころ いってんか", ["キッチン"], []),  # 関西 〜てんか
        ("はみがきするとこ いって", ["洗面所"], []),
        ("ダイニングいって まちごうた キッチンや", ["キッチン"], []),  # 関西 まちごうた: a correction
        ("おふろ…やなくて せんめんじょやな せんめんじょいって", ["洗面所"], []),  # やなくて after a pause
    ],
)
def test_blind30_forms(text, visit, waits):
    """Session 8, from blind30 (関西弁, spoken, mostly kana) after its measurement."""
    r = read(text, JA, "ja")
    assert _visit(r) == visit and [s for _, s in r.waits] == waits


def test_a_delay_in_kana_stays_refused():
    with pytest.raises(InstructionError, match="じゅっぷんご"):  # quoted as said
        read("じゅっぷんごに リビングいって", JA, "ja")
