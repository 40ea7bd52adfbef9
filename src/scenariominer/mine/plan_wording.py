"""Putting a description's wording in the one form the phrase tables read.

:func:`normalised_text` lower-cases a description, turns number words into digits, feet into
metres and lists of road users into "X or Y or Z", drops a leading search verb ("find all
instances of ...") and examples after "e.g.", puts verbs in their -ing form ("a car turns left")
and applies the rewordings of :mod:`scenariominer.mine.plan_rewordings` (other wordings of the same
phrase: "the ego's lane" -> "the same lane as the ego vehicle"). It re-exports the road-user patterns
of :mod:`scenariominer.mine.plan_nouns` (:data:`NOUN`, :data:`NP`, :data:`SUBJECT`) that
:mod:`scenariominer.mine.plan_reader` matches with.
"""

from __future__ import annotations

import re

from scenariominer.mine.plan_coaching import coaching_remark
from scenariominer.mine.plan_commit import commit_message
from scenariominer.mine.plan_documents import camel_words, document_wording
from scenariominer.mine.plan_everyday import everyday_wording, figure_marks
from scenariominer.mine.plan_filters import filter_wording
from scenariominer.mine.plan_formal import formal_wording
from scenariominer.mine.plan_formula import spreadsheet_formula
from scenariominer.mine.plan_graph import graph_pattern
from scenariominer.mine.plan_instructions import instruction_wording
from scenariominer.mine.plan_learners import learner_wording
from scenariominer.mine.plan_logic import logic_rule
from scenariominer.mine.plan_methods import methods_wording
from scenariominer.mine.plan_narrative import present_tense
from scenariominer.mine.plan_news import news_wording
from scenariominer.mine.plan_notes import plain_notes
from scenariominer.mine.plan_nouns import CATEGORY_RE, DETERMINER, MODIFIER_RE, NOUN, NOUN_PHRASE, NP, SUBJECT
from scenariominer.mine.plan_plain import plain_wording
from scenariominer.mine.plan_quantifiers import quantified_set
from scenariominer.mine.plan_query_api import query_api_request
from scenariominer.mine.plan_registers import register_wording, request_sentence
from scenariominer.mine.plan_rewordings import _CLEAR_ROAD, _REWORDINGS, _SHARED_VERB
from scenariominer.mine.plan_scenic import scenic_program
from scenariominer.mine.plan_sets import set_wording
from scenariominer.mine.plan_spelling import corrected_spelling
from scenariominer.mine.plan_spoken import spoken_request
from scenariominer.mine.plan_steps import procedure_wording
from scenariominer.mine.plan_telegram import telegram_wording
from scenariominer.mine.plan_translated import translated_wording
from scenariominer.mine.plan_witness import witness_wording
from scenariominer.mine.plan_yaml import yaml_block

__all__ = [
    "CATEGORY_RE",
    "DETERMINER",
    "MODIFIER_RE",
    "NOUN",
    "NOUN_PHRASE",
    "NP",
    "SUBJECT",
    "normalised_text",
]


WORD_NUMBERS = {
    "one": "1", "two": "2", "three": "3", "four": "4", "five": "5", "six": "6", "seven": "7",
    "eight": "8", "nine": "9", "ten": "10", "eleven": "11", "twelve": "12", "fifteen": "15",
    "twenty": "20", "twenty-five": "25", "thirty": "30", "forty": "40", "fifty": "50", "sixty": "60",
    "hundred": "100",
}  # fmt: skip
ORDINALS = {"first": "1", "second": "2", "third": "3", "fourth": "4", "fifth": "5"}
#: Verbs in the base or present form, as the tables read them ("a car turns left", "car that
#: turn to the right" -> "turning"): word -> the -ing form.
VERB_FORMS: dict[str, str] = {
    **{w: "turning" for w in ("turn", "turns")},
    **{w: "walking" for w in ("walk", "walks")},
    **{w: "running" for w in ("run", "runs")},
    **{w: "driving" for w in ("drive", "drives")},
    **{w: "going" for w in ("go", "goes")},
    **{w: "moving" for w in ("move", "moves")},
    **{w: "stopping" for w in ("stop", "stops")},
    **{w: "crossing" for w in ("cross", "crosses")},
    **{w: "following" for w in ("follow", "follows")},
    **{w: "approaching" for w in ("approach", "approaches")},
    **{w: "accelerating" for w in ("accelerate", "accelerates")},
    **{w: "decelerating" for w in ("decelerate", "decelerates")},
    **{w: "braking" for w in ("brake", "brakes")},
    **{w: "overtaking" for w in ("overtake", "overtakes")},
    **{w: "passing" for w in ("pass", "passes")},
    **{w: "waiting" for w in ("wait", "waits")},
    **{w: "riding" for w in ("ride", "rides")},
    **{w: "merging" for w in ("merge", "merges")},
    **{w: "swerving" for w in ("swerve", "swerves")},
    **{w: "facing" for w in ("face", "faces")},
    **{w: "heading" for w in ("head", "heads")},
    **{w: "travelling" for w in ("travel", "travels")},
    **{w: "standing" for w in ("stand", "stands")},
    **{w: "changing" for w in ("change", "changes")},
    **{w: "slowing" for w in ("slow", "slows")},
    **{w: "speeding" for w in ("speed", "speeds")},
    **{w: "tailgating" for w in ("tailgate", "tailgates")},
    **{w: "making" for w in ("make", "makes")},
    **{w: "taking" for w in ("take", "takes")},
    **{w: "sharing" for w in ("share", "shares")},
    # a news story's verbs
    **{w: "walking" for w in ("stroll", "strolls")},
    **{w: "stepping" for w in ("step", "steps")},
    **{w: "darting" for w in ("dart", "darts")},
    **{w: "dashing" for w in ("dash", "dashes")},
    **{w: "jogging" for w in ("jog", "jogs")},
    **{w: "creeping" for w in ("creep", "creeps")},
    **{w: "crawling" for w in ("crawl", "crawls")},
    **{w: "hitting" for w in ("hit", "hits")},
    **{w: "slamming" for w in ("slam", "slams")},
    **{w: "pulling" for w in ("pull", "pulls")},
    **{w: "sitting" for w in ("sit", "sits")},
    **{w: "squeezing" for w in ("squeeze", "squeezes")},
    **{w: "zipping" for w in ("zip", "zips")},
    **{w: "racing" for w in ("race", "races")},
    **{w: "cruising" for w in ("cruise", "cruises")},
    **{w: "rolling" for w in ("roll", "rolls")},
}
#: Words before which a verb form is a noun or an adjective instead ("a right *turn*", "*stop*
#: sign", "the *brakes*", "a *slow* car").
VERB_BLOCKERS_BEFORE = frozenset(
    {"a", "an", "the", "right", "left", "u", "full", "sudden", "momentary", "brief", "short", "to"}
    | {"their", "its", "his", "her", "no", "hard", "emergency", "lane", "temporary", "complete", "crawling"}
    | {"of", "for"}
)
#: Words after which ... : "stop *sign*", "turn *signal*", "speed *limit*", "slow *car*".
VERB_BLOCKERS_AFTER = frozenset({"sign", "signs", "signal", "signals", "limit", "bump", "light", "lights"})
#: Verbs that only count with their particle: "speed *up*", "slow *down*", "change *lane(s)*".
VERB_PARTICLES = {"speeding": ("up",), "slowing": ("down",), "changing": ("lane", "lanes")}


#: "find (all) (instances of)": words that ask for the result rather than describe it.
_SEARCH_VERB = re.compile(
    r"^(?:please )?(?:(?:could|can|would|will) you (?:please |kindly |maybe )*)?"
    r"(?:(?:(?:i |we )?(?:need|want|would like|am looking for|are looking for)"
    r"|i'd like|we'd like|i'm looking for|we're looking for)"
    r"(?: to (?:find|see|get))?|retrieve|find|show(?: me)?|identify|get|list|search for|look for|give me"
    r"|return|select|extract|locate|pull(?: up)?|which|what|are there|is there|how many|do any|does any"
    r"|seek|request|(?:i |we )?require"
    r"|collect|count|tally|log|record|(?:1|one) event(?: (?:per|for))?"
    r"|how often (?:do|does|is|are)(?: there)?|(?:when|where) (?:do|does|did|is|are)(?: there)?"
    r"|list every (?:time|moment|instance|case)(?: (?:that|when|where))?)"
    r"(?: (?:all|every|each|any|the|an?))?(?: (?:instances?|cases?|examples?|occurrences?|situations?"
    r"|scenarios?|scenes?|frames?|moments?|events?|clips?|times?|occasions?|stretch(?:es)? of time|periods?"
    r"|spells?|episodes?|instants?)"
    r"(?: (?:of|where|with|in which|when|that))?)?(?: there(?:'s| is| are))?\s+"
)
#: "..., counts as one (event)", "... is counted": what is done with the result, not part of it.
_COUNTS_AS_ONE = re.compile(r",?\s+(?:counts?|is counted|are counted)(?: as (?:1|one)(?: event)?)?$")
#: A list of three or more road users ("pedestrians, cyclists or scooters").
_LIST = re.compile(
    rf"(?<![\w-])(?P<head>{CATEGORY_RE})(?P<tail>(?:,\s*(?:other\s+)?(?:{CATEGORY_RE}))+),?\s+"
    rf"(?P<conj>or|and)\s+(?P<last>(?:other\s+)?(?:{CATEGORY_RE}))(?![\w-])"
)
#: "heavy vehicles (trucks, box trucks or buses) ...": the road users in brackets name the subject.
_BRACKETED_LIST = re.compile(rf"\((?P<items>(?:{CATEGORY_RE})(?:,\s*(?:{CATEGORY_RE}))+)\)")
_BRACKETED_SUBJECT = re.compile(rf"^(?:an? |the |all )?(?:[\w-]+ ){{0,4}}[\w-]+\s*\((?P<noun>{NOUN})\)")


def _listed_road_users(text: str) -> str:
    """``text`` with a list of road users joined by "or" and a bracketed subject list put first.

    "pedestrians, cyclists or scooters near X" -> "pedestrians or cyclists or scooters near X";
    "heavy vehicles (trucks, box trucks or buses) going ..." -> "trucks or box trucks or buses
    going ...".
    """
    text = _LIST.sub(
        lambda m: " or ".join(
            [m["head"], *(p.strip() for p in m["tail"].split(",") if p.strip()), m["last"]]
        ),
        text,
    )
    # "trucks of any kind (box trucks, trucks, truck cabs)": a bracketed list without "or"
    text = _BRACKETED_LIST.sub(
        lambda m: "(" + " or ".join(n.strip() for n in m["items"].split(",")) + ")", text
    )
    bracketed = _BRACKETED_SUBJECT.match(text)
    subject = SUBJECT.match(text)
    if bracketed is not None and subject is not None:
        # the adjectives before the bracket stay: "parked trucks (truck or box truck)"
        text = subject["mods"] + bracketed["noun"] + text[bracketed.end() :]
    return text


#: Keys of a specification line ("actor: vehicle; manoeuvre: right turn; location: ..."), by role.
_SPEC_ROLES: dict[str, str] = {
    **dict.fromkeys(
        (
            "actor", "subject", "agent", "object", "target", "road user", "type", "category", "actors",
            "objects", "agents", "targets", "categories", "class", "object type", "actor type",
            "object class",
        ),
        "actor",
    ),
    "ego": "ego",
    **dict.fromkeys(
        (
            "manoeuvre", "maneuver", "manoeuver", "action", "behaviour", "behavior", "motion", "activity",
            "state", "status",
        ),
        "motion",
    ),
    **dict.fromkeys(("facing", "heading", "direction", "orientation"), "bearing"),
    **dict.fromkeys(("range", "distance", "radius", "proximity", "within"), "range"),
    **dict.fromkeys(
        (
            "condition", "relation", "location", "context", "constraint", "where", "place", "map",
            "area", "speed", "filter", "interaction", "trigger", "situation", "other", "with", "event",
        ),
        "clause",
    ),
}  # fmt: skip
_SPEC_PART = re.compile(r"^\s*(?P<key>[a-z][a-z ]*?)\s*[:=]\s*(?P<value>\S.*?)\s*$")
#: A manoeuvre named by a noun: "right turn" -> "turning right", "lane change to the left".
_MANOEUVRE_NOUNS: tuple[tuple[re.Pattern[str], str], ...] = (
    (re.compile(r"^(?:an? )?(left|right)[- ]turns?$"), r"turning \1"),
    (re.compile(r"^(?:an? )?turns?(?: to the (left|right))?$"), r"turning \1"),
    (
        re.compile(r"^(?:an? )?lane[- ]changes?(?P<rest>(?: to the (?:left|right))?)$"),
        r"changing lanes\g<rest>",
    ),
)


#: A place named by its bare noun in a specification ("context: intersection").
_SPEC_PLACE = re.compile(r"^(?:an? |the )?(intersection|junction|crosswalk|pedestrian crossing)s?$")
#: A bare distance in a specification ("range: 20 m"): a limit on the part before it.
_SPEC_DISTANCE = re.compile(
    r"^(?:within |up to |under |less than |<=? ?)?(\d+(?:\.\d+)?) ?(m|metres?|meters?|ft|feet)$"
)
#: "relation: oncoming traffic relative to ego": the direction of travel it names.
_SPEC_ONCOMING = re.compile(
    r"^oncoming(?: traffic| vehicles?)? (?:relative to|with respect to|to|for|towards?) (.+)$"
)
#: A road user first in a part ("two or more vehicles ahead ..."): a "with" clause.
_SPEC_USER = re.compile(rf"(?:(?:an?|another|some|\w+ or more|at least \w+|\d+|no|other|the) )?{NP}")


def _spec_value(role: str, key: str, value: str) -> str:
    """One part of a specification as the words of its clause ("facing: toward X" -> "facing toward X")."""
    if role == "bearing" and not re.match(r"\w+ing\b", value):
        return f"{'moving' if key == 'direction' else key} {value}"
    if _SPEC_PLACE.match(value):  # "context: intersection": at one
        return "at " + _SPEC_PLACE.sub(r"the \1", value)
    if (oncoming := _SPEC_ONCOMING.match(value)) is not None:
        return f"travelling in the opposite direction to {oncoming[1]}"
    return f"with {value}" if _SPEC_USER.match(value) else value


def _spec_lines(text: str) -> str:
    """A specification of ``key: value`` parts as one sentence, or ``text`` when it is none.

    "actor: vehicle; manoeuvre: right turn; condition: a pedestrian crosses in front of it" ->
    "vehicle turning right and with a pedestrian crosses in front of it"; "ego: turning left |
    location: on an intersection" -> "the ego vehicle turning left and on an intersection". At
    least two parts, separated by ";" or "|" (or else by commas); a key the table does not know
    ("relative position: ...") is read as a condition once an actor or the ego is named.
    """
    parts = [p for p in re.split(r"\s*[;|]\s*", text.strip().rstrip(".")) if p]
    if len(parts) < 2:  # "actor=vehicle, maneuver=lane change left": parts between commas
        parts = [p for p in re.split(r"\s*,\s*", text.strip().rstrip(".")) if p]
    found = [_SPEC_PART.match(p) for p in parts]
    if len(parts) < 2 or any(f is None for f in found):
        return text
    keys = [f["key"] for f in found if f is not None]
    # a key of its own ("relative position: ...") is a condition, once an actor is named
    if not any(_SPEC_ROLES.get(k) in ("actor", "ego") for k in keys) and any(
        k not in _SPEC_ROLES for k in keys
    ):
        return text
    actor, clauses = "", []
    for f in found:
        assert f is not None
        role, value = _SPEC_ROLES.get(f["key"], "clause"), f["value"]
        if role == "actor":
            actor = value
        elif role == "ego":
            actor = actor or "the ego vehicle"
            clauses.append(value)
        elif role == "motion":
            for pattern, replacement in _MANOEUVRE_NOUNS:
                value = pattern.sub(replacement, value).rstrip()
            clauses.insert(0, value)
        elif role == "range" and (distance := _SPEC_DISTANCE.match(value)) and clauses:
            # "range: 20 m": the limit of the part before it ("approaching the ego vehicle within 20 m")
            clauses[-1] += f" within {distance[1]} {distance[2]}"
        else:
            clauses.append(_spec_value(role, f["key"], value))
    if not actor:
        return text
    return f"{actor} {' and '.join(clauses)}".strip()


def _metres(feet: str) -> str:
    """A number of feet in metres, to the millimetre ("20" -> "6.096")."""
    return f"{round(float(feet) * 0.3048, 3):g}"


def normalised_text(description: str) -> str:
    """Lower case, single spaces, no final full stop, number words as digits ("three" -> "3").

    A place in a line of vehicles is put in the one form the tables read: "the third car forward
    from X" -> "the car 3 cars forward from X"; "two cars back from X" (no subject) -> "vehicle 2
    cars back from X".
    """
    # typing slips put right and CamelCase names split, a parameter block's lines (it needs its
    # line breaks), then the wording of a ticket, a clause or a requirement around the request, a
    # set (its gloss after the closing brace is dropped), a request among other sentences
    description = re.sub(r"(?<=/s) ?²", "^2", description)  # "m/s²": the "m/s^2" the tables read
    text = corrected_spelling(
        camel_words(
            logic_rule(
                quantified_set(
                    spreadsheet_formula(
                        graph_pattern(
                            telegram_wording(
                                procedure_wording(
                                    commit_message(scenic_program(query_api_request(description)))
                                )
                            )
                        )
                    )
                )
            )
        ).lower()
    )
    text = spoken_request(coaching_remark(translated_wording(figure_marks(text))))
    text = witness_wording(methods_wording(document_wording(" ".join(yaml_block(text).split()))))
    text = request_sentence(set_wording(text))
    text = present_tense(
        _spec_lines(
            learner_wording(
                plain_notes(
                    formal_wording(news_wording(register_wording(instruction_wording(filter_wording(text)))))
                )
            )
        )
    )
    # examples between commas add nothing to read ("vehicles that were not cars, like trucks, ...")
    text = re.sub(
        r", (?:(?:things|ones|stuff|objects) )?(?:like|such as|e\.g\.?|for example|including) [^,()]*,",
        " ",
        text,
    )
    text = " ".join(_listed_road_users(text).replace(",", " ").split()).rstrip(".!?")
    # "jaywalkers, i.e. pedestrians on the road ...": the definition after "i.e." when it names a
    # road user first
    named, ie, definition = text.partition(" i.e. ")
    if ie and SUBJECT.match(definition) and len(named.split()) <= 3:
        text = definition
    # examples after the description add nothing to read ("..., e.g. in a parking lot")
    text = re.sub(r"\s*\(?\b(?:e\.g\.?|i\.e\.?|for example|for instance|such as)(?:\s.*)?$", "", text)
    # brackets: an explanation with "etc" adds nothing, a word repeating the verb neither; other
    # bracketed words are read as plain words ("... (within 20 m)", "(> 1 m/s)")
    text = re.sub(r"\([^()]*\betc\b[^()]*\)|\((?:overtaken|overtaking|passing|lane change)\)", " ", text)
    # "with a clear road ahead (no vehicle within 30 m in front)": the definition in brackets
    text = re.sub(rf"\bwith {_CLEAR_ROAD} \((no [^()]*)\)", r"with \1", text)
    text = " ".join(text.replace("(", " ").replace(")", " ").split())
    text = re.sub(r"\s*(?:>=|≥)\s*", " at least ", text)
    text = re.sub(r"\s*(?:<=|≤)\s*", " at most ", text)
    text = re.sub(r"\s*>\s*", " more than ", text)
    text = re.sub(r"\s*<\s*", " less than ", text).strip()
    # everyday words ("the car we are in", "5 meters every second", "3 meters or closer")
    text = everyday_wording(text)
    # units in words: "metres a second", "metre per second squared", "miles an hour"
    text = re.sub(r"\b(?:metres?|meters?) (?:a|per) second (?:squared|per second)\b", "m/s^2", text)
    text = re.sub(r"\b(?:metres?|meters?) (?:a|per) second\b", "m/s", text)
    text = re.sub(r"\b(?:kilometres?|kilometers?) (?:an|per) hour\b", "km/h", text)
    text = re.sub(r"\bmiles? (?:an|per) hour\b", "mph", text)
    # a search verb before the request ("find all instances of trucks ...")
    text = _SEARCH_VERB.sub("", text)
    # feet as metres ("within 20 feet": 6.096 m)
    text = re.sub(r"\b(\d+(?:\.\d+)?) ?(?:feet|foot|ft)\b", lambda m: f"{_metres(m.group(1))} m", text)
    # "cross traffic: vehicles moving perpendicular to the ego": the definition after the colon
    # ("a metric's name: count each bus near an intersection": without its search verb, and
    # without "... counts as one" after it)
    named, colon, definition = text.partition(": ")
    if colon:
        definition = re.sub(
            r"^(?:each|every|another) ", "", _COUNTS_AS_ONE.sub("", _SEARCH_VERB.sub("", definition))
        )
    if colon and SUBJECT.match(definition):
        text = definition
    elif colon and (subject := SUBJECT.match(named)) and re.match(r"(?:ones|those) ", definition):
        # "oncoming vehicles: ones travelling ...": the named road user, as defined
        text = subject["noun"] + " " + definition.split(" ", 1)[1]
    text = re.sub(r"\bego-(vehicle|car)\b", r"ego \1", text)
    # "the AV('s)": the ego vehicle, the one name the rewordings below know it by
    text = re.sub(r"\b(?:the )?(?:av|adv|sdv)\b", "the ego vehicle", text)
    text = re.sub(r"\b(" + "|".join(WORD_NUMBERS) + r")\b", lambda m: WORD_NUMBERS[m.group(1)], text)
    # "the nearest car ahead", "the car immediately in front of us": the first in line
    text = re.sub(r"\b(?:nearest|closest) (cars?|vehicles?) (?=ahead|in front|behind)", r"first \1 ", text)
    text = re.sub(
        r"\b(?:the )?(cars?|vehicles?) (?:right|immediately) (?=ahead of|in front of|behind)",
        r"the first \1 ",
        text,
    )
    text = re.sub(
        r"\b(" + "|".join(ORDINALS) + r") (cars?|vehicles?) (?=ahead|in front|forward|behind|back)",
        lambda m: f"{m.group(2)} {ORDINALS[m.group(1)]} {m.group(2)} ",
        text,
    )
    text = re.sub(r"^(\d+ (?:cars?|vehicles?) (?:ahead|in front|forward|behind|back))", r"vehicle \1", text)
    return plain_wording(_reworded(text))


def _ing_forms(text: str) -> str:
    """``text`` with verbs in the base or present form put in the -ing form the tables read.

    "a car turns left" -> "a car turning left", "car change lane to the left" -> "car changing lane
    to the left"; a noun or adjective of the same spelling stays ("a right turn", "stop sign", "the
    brakes", "speed limit"), and so does a verb that needs its particle and lacks it ("speed").
    """
    words = text.split(" ")
    for i, word in enumerate(words):
        form = VERB_FORMS.get(word)
        before = words[i - 1] if i > 0 else ""
        after = words[i + 1] if i + 1 < len(words) else ""
        if form is None or i == 0 or before in VERB_BLOCKERS_BEFORE or after in VERB_BLOCKERS_AFTER:
            continue
        if before == "bus" and form == "stopping":
            continue  # a bus stop
        if form in VERB_PARTICLES and after not in VERB_PARTICLES[form]:
            continue
        words[i] = form
    return " ".join(words)


def _reworded(text: str) -> str:
    """``text`` with :data:`_REWORDINGS` applied and a shared relation verb's object repeated.

    "vehicles approaching and facing a stopped car" -> "vehicles approaching a stopped car facing
    a stopped car", so each verb is read as its own relation.
    """
    text = _ing_forms(text)
    for pattern, replacement in _REWORDINGS:
        text = " ".join(pattern.sub(replacement, text).split())
    return _SHARED_VERB.sub(lambda m: f"{m['v1']} {m['obj']} {m['v2']} {m['obj']}", text)
