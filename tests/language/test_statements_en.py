"""Rule 3b of the English asides (spcotmhp/language/statements_en.py): a clause stating something of someone other
than the robot is passed over; a clause holding a place, a class of the instruction, "to"/"in" before anything but a
length of time, or a length where the instruction waits without one stays, to be read or refused."""

from __future__ import annotations

import pytest

from spcotmhp.errors import InstructionError
from spcotmhp.language.reading import read
from tests.helpers.vocabulary import PLACE_WORDS_EN

EN = PLACE_WORDS_EN


@pytest.mark.parametrize(
    "text, goal",
    [
        ("The entrance please, my grandson is coming over.", "entrance"),
        ("we've got people coming over, go to the dining room", "dining"),
        ("Go to the entrance, my taxi is here.", "entrance"),
        ("Head into the kitchen, lunch is nearly ready.", "kitchen"),
        ("Go and sit in the living room, I'll join you in a minute", "living"),
        ("Please go to the corridor, you are blocking the door.", "corridor"),
        ("Go to the toilet, I want to show the guests how you move", "toilet"),
        ("Could you go to the washroom? Our guest is staying there.", "washroom"),  # a noun that also names a room
        ("Go to the storage room, I'll be there in a moment.", "storeroom"),
        ("Go to the storage room, I'll be there soon.", "storeroom"),  # the speaker's time, not the robot's
        ("Please go to the toilet, we'll be along shortly.", "toilet"),
        ("Hi there! Would you go to the entrance? My taxi should be here soon. Thank you!", "entrance"),
    ],
)
def test_a_statement_of_someone_else_is_passed_over(text, goal):
    r = read(text, EN, "en")
    assert [p.words[0] for p in r.visit] == [goal] and r.waits == () and r.speed is None
    assert r.heard, "what was passed over is said"


@pytest.mark.parametrize(
    "text",
    [
        "go to the kitchen, we're going to the garage",  # a motion somewhere: the garage is refused
        "wait in the kitchen, I'll be back in ten minutes",  # the length may be the wait's
        "go to the bedroom, the big one is mine",  # a size: which bedroom?
        "go to the kitchen, park there",
        "go to the kitchen, you are going to the bath",  # "you are" before a motion somewhere
        "go to the bath, it's for tonight",  # "it" may be the instruction: tonight is when to go
        "go to the bath, I need you there tonight",  # the robot is in the clause: its time
        "go to the kitchen, we'll be along to the garage",  # a place after the particle
    ],
)
def test_what_a_statement_may_not_hold_keeps_it_in_the_instruction(text):
    with pytest.raises(InstructionError):
        read(text, EN, "en")


def test_a_statement_with_a_place_is_read_with_it():
    """A place keeps the clause in the instruction: "my mum is in the bath" is not passed over as talk."""
    with pytest.raises(InstructionError):
        read("go to the kitchen, my mum is in the bath", EN, "en")


def test_an_order_to_speed_up_is_read_not_passed_over():
    # "speed" is no subject: the clause is an order, read as a speed (it was refused before 'speed it up' was FAST)
    assert read("go to the living room, but like, speed it up", EN, "en").speed == "fast"
