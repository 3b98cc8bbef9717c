"""Words of the synthetic environments: room names per kind of building and the teaching utterance templates.

Every place name is one English token (a "meeting room" is ``meeting``). Names repeat on purpose (several
bedrooms, many offices, every corridor place is ``corridor``), and the templates share their function words
across places, as real teaching utterances do.
"""

from __future__ import annotations

CORRIDOR = "corridor"
LIVING = "living"

#: Names given in this order of priority to the rooms of a flat (after the living room), then FILLER_NAMES.
FLAT_NAMES = [
    "kitchen",
    "bedroom",
    "bath",
    "toilet",
    "bedroom",
    "entrance",
    "dining",
    "washroom",
    "storeroom",
    "bedroom",
]
#: The same for a house (which has an entrance and corridors of its own).
HOUSE_NAMES = [
    "kitchen",
    "bedroom",
    "bath",
    "toilet",
    "bedroom",
    "dining",
    "washroom",
    "bedroom",
    "storeroom",
]
#: Special rooms of an office (about a third of its rooms), the others from FILLER_NAMES["office"].
OFFICE_SPECIAL = [
    "meeting",
    "printer",
    "kitchen",
    "toilet",
    "lab",
    "storeroom",
    "meeting",
    "lounge",
    "library",
    "server",
    "toilet",
    "lab",
    "reception",
]
FILLER_NAMES = {
    "flat": ["bedroom", "storeroom"],
    "house": ["bedroom", "storeroom"],
    "office": ["office", "office", "office", "meeting", "lab"],
}
#: Rooms people walk through first get these names (a kitchen before a toilet); the rest stay at the ends.
THROUGH_ORDER = ["kitchen", "dining", "entrance", "washroom", "bedroom", "storeroom", "bath", "toilet"]

#: Every place name the generator can give; word noise draws substitute names from it.
PLACE_VOCABULARY = sorted({CORRIDOR, LIVING, "office", *FLAT_NAMES, *HOUSE_NAMES, *OFFICE_SPECIAL})

#: Teaching utterances; ``{}`` is the place name.
TEMPLATES = [
    "this is the {}",
    "the name of this place is {}",
    "{}",
    "you are in the {}",
    "here is the {}",
    "we are in the {}",
    "this place is called {}",
    "it is the {}",
]
#: Words an inserted-noise word is drawn from besides the place names and the templates' function words.
FILLER_WORDS = ["um", "uh", "okay", "now", "so", "well", "robot", "look"]
FUNCTION_WORDS = sorted({w for t in TEMPLATES for w in t.split() if w != "{}"})
#: Every word an utterance can contain.
ALL_WORDS = sorted({*PLACE_VOCABULARY, *FUNCTION_WORDS, *FILLER_WORDS})
