"""Requests that came out of a machine translator: their literal words put in the tables' words.

Engineers who write in German, Chinese or Japanese and pass the request through a translator send
English with literal compounds and odd prepositions: "foot-goers which are standing directly upon
the zebra crossing", "box-type load cars in vicinity of intersection, within distance of 10
meter", "omnibus which is moving with the speed of more than 2 meter per second", "the own car",
"make the turning into the left direction", "inside of 5 meter surrounding it", "2 meter per
second square". :func:`translated_wording` rewrites such phrases (lower case, before number words
and units are read) into the words the phrase tables know; each rewrite keeps the meaning, and a
phrase it does not know is left as written.
"""

from __future__ import annotations

import re

__all__ = ["translated_wording"]

_N = r"\d+(?:\.\d+)?"
_SIDE = r"(left|right)"

_VERB = r"(?:make|makes|making|do|does|doing|carry out|carries out|perform|performs)"
#: (pattern, replacement), in the order they are applied.
_RULES: tuple[tuple[str, str], ...] = (
    # "please search the ...", "please give all objects of the type bollard"
    (r"^(?:please )?(?:search|give|output)(?: me)?(?: all| every)?(?: the)?"
     r"(?: objects? (?:of|with) (?:the )?(?:type|category|class))? ", "find "),
    # literal compounds for road users
    (r"\bfoot[- ]?goers?\b|\bpedestrian persons?\b|\bwalking persons?\b", "pedestrians"),
    (r"\bbox(?:-type| type)? load[- ]cars?\b|\bbox load[- ]cars?\b", "box trucks"),
    (r"\bload[- ]?cars?\b|\bfreight cars?\b|\blorr(?:y|ies)\b", "trucks"),
    (r"\bomnibus(?:es)?\b", "bus"),
    (r"\bnormal (?:passenger )?cars?\b", "regular vehicles"),
    (r"\b(?:(?:the|our|your|my) )?own (?:car|vehicle)\b|\bself[- ]car\b|\bhost (?:car|vehicle)\b",
     "the ego vehicle"),
    (r"\b(?:the |a )?crossroads?(?: area)?(?: itself)?\b", "an intersection"),
    (r"\bthe lane dedicated (?:for|to) (?:the )?bus(?:es)?\b|\bthe bus-?dedicated lane\b", "a bus lane"),
    # units written out literally
    (rf"\b({_N}) ?(?:meters?|metres?) per second (?:square|squared|quadrat)\b", r"\1 m/s^2"),
    (rf"\b({_N}) ?m/s ?(?:square|squared|2)\b", r"\1 m/s^2"),
    (rf"\b(?!1 )({_N}) ?(?:meter|metre)\b(?! per)", r"\1 m"),  # "1 metre" is English
    # distances
    (rf"\b(?:inside|within) (?:of )?({_N}) ?m(?: distance)?(?: (?:surrounding|around) (?:it|them))?\b",
     r"within \1 m"),
    (rf"\bin (?:the )?vicinity of (an? |the )?(\w+),? within (?:the )?distance of ({_N}) ?m\b",
     r"within \3 m of an \2"),
    (rf",? (?:minimum|at minimum|at least) ({_N}) (\w+) in ({_N}) ?m\b", r" with at least \1 \2 within \3 m"),
    (r"\b(?:which )?(?:have|has|having) ([\w ]+?) around(?= with at least)", ""),
    # states and actions
    (rf"\b{_VERB} (?:the |a )?(?:turning|turn) (?:in)?to (?:the )?{_SIDE}(?: direction| side)?\b",
     r"turning \1"),
    (rf"\b(?:carry|carries) out (?:the |a )?lane chang(?:e|ing) to (?:the )?{_SIDE}(?: side)?\b",
     r"changing lanes to the \1"),
    (r"\b(?:make|makes|making|do|does) no turning(?: at all)?\b", "not turning"),
    (r"\b(?:is |are )?(?:in|at) (?:the |a )?temporary standstill(?: with speed almost zero)?\b",
     "momentarily stopped"),
    (r",? but not the ones parked (?:over|during) the whole (?:recording|record|log)\b", " not parked"),
    (r"\b(?:which|that) (?:is|are) active,? that means (not parked)(?: the whole time)?\b", r"\1"),
    (r",? both the parked ones and the ones standing only for (?:a )?short moment\b", ""),
    (r"\bwith the speed of (?=more than|less than|over|under)", ""),
    (r"\bmoving (more than|over) (?=\d)", "moving faster than "),
    (r"\b(?:drive|drives|driving) with (?:the )?(?:velocity|speed) (?=between)", "moving at a speed "),
    (r"\b(?:perform|performs|doing|does) (?:a |the )?strong braking,? the deceleration is"
     r" (?:more than|over)", "decelerating at more than"),
    (rf"\b(?:does |do )?accelerat(?:e|es|ing) strongly with (?:over|more than) ({_N} ?m/s\^2)"
     r"(?: forward)?\b", r"accelerating at more than \1"),
    (rf"\b(?:doing|does|do|performing|with) the lateral acceleration to (?:its|their|the) {_SIDE} side"
     rf" (?:over|more than) ({_N} ?m/s\^2)", r"with a lateral acceleration of more than \2 to the \1"),
    (r"\b(?:running|moving|driving|going|walking) fast,? the (?:velocity|speed) (?:is )?"
     r"(?:higher|more|greater|faster) than\b", "moving faster than"),
    # relations
    (r"\b(?:drives|drive|driving|is driving|are driving) following(?: behind)?\b", "following"),
    (r"\bfollowing (another|an?) (\w+) in the same lane ahead\b", r"following \1 \2"),
    (r"\bmoving in (?:the )?direction (?:toward|towards|to) (the ego vehicle|\w+)"
     r"(?: and approaching it)?\b", r"moving toward \1"),
    (r"\bwhose (?:body )?front is (?:pointing|directed|oriented) (?:to|toward|towards)\b", "facing"),
    (r"\bcrossing over in (?:the )?front of\b", "crossing in front of"),
    (r"\b(?:standing or walking|located|staying|existing|exists?) (?:directly )?(?:up)?on "
     r"|\bstanding (?:directly )?upon ", "on "),
    (r"\b(?:located )?on inside of\b", "on"),
    (r"\b(?:surface|area),? overlap(?:ping)? with it\b", ""),
    (r"\b(?:located )?at the opposite side of (?:the )?road relative to\b",
     "on the opposite side of the road from"),
    (r"\b(?:exists? |located |is )?in (?:the )?front direction of\b", "ahead of"),
    (r"\bin (?:its|their) front\b", "in front of it"),
    (rf"\bon (?:its|their) {_SIDE} hand side,? closely beside of it\b", r"on its \1 side"),
    (r"\bclosely beside of it\b|\bbeside of it\b", "beside it"),
    (rf"\bon (?:the )?{_SIDE} side by (other|another) vehicle passing them from behind to ahead\b",
     r"on the \1 side by \2 vehicle"),
    (r"\bcounter direction\b", "opposite direction"),
    (r"\bclose within\b", "within"),
    (r",? namely (?:which|that) [^,]+$", ""),
    (r"\band also (\w+) together,? all of them which\b", r"or \1"),
    (r"\bduring (?:the )?whole record(?:ing)?\b", "the whole time"),
    (r",? the short post for blocking of cars\b", ""),
)  # fmt: skip
_REWRITES = tuple((re.compile(pattern), replacement) for pattern, replacement in _RULES)


def translated_wording(text: str) -> str:
    """``text`` (lower case) with a translator's literal phrases in the tables' words.

    "foot-goers who are located on inside of the crossroad area itself" -> "pedestrians who are on
    an intersection"; "omnibus which is moving with the speed of more than 2 meter per second" ->
    "bus which is moving faster than 2 m per second".
    """
    for pattern, replacement in _REWRITES:
        text = pattern.sub(replacement, text)
    return re.sub(r"[ \t]{2,}", " ", text)  # new lines stay: a YAML block is read by its lines
