"""The phrase tables of the description reader (:mod:`scenariominer.mine.plan_reader`).

Each table maps English phrasing to the mining predicates: road users (:data:`CATEGORY_PHRASES`),
their adjectives (:data:`MODIFIERS`) and the phrases after the subject (:data:`PHRASES`: motions,
places on the map, relations to other road users). A stated number is used in the predicate's
unit; a phrase without one takes the predicate's default (RefAV's), unless the phrase itself says
how much ("fast" 10 m/s, "very close to" 5 m, "braking hard" -3 m/s^2, "directly ahead" 1 m aside).
Pure data: the reader compiles the patterns and applies them.
"""

from __future__ import annotations

from dataclasses import dataclass

from scenariominer.mine.plan_road_users import CATEGORY_PHRASES

__all__ = [
    "CATEGORY_PHRASES",
    "COUNT_KEYWORD",
    "EGO",
    "EXCEPT",
    "FILLERS",
    "HARD_BRAKING",
    "LAST",
    "MODIFIERS",
    "PHRASES",
    "SLOW",
    "TO_MPS",
    "Phrase",
]


#: A speed condition for "moving" and for the riding/walking verbs (the predicate's default).
MOVING = ("has_velocity", "min_velocity=0.5")
STOPPED = ("has_velocity", "min_velocity=0, max_velocity=0.5")
#: "stopped": at rest at the timestamp, parked objects included (the Argoverse 2 scenario-mining
#: ground truth of "stopped car" refers to the parked cars too); compiled by
#: :mod:`scenariominer.mine.plan_program` as ``stationary`` or ``has_velocity(<= 0.5 m/s)``.
STOPPED_OR_PARKED = ("stopped", None)
#: "slow": moving, below 5 m/s (18 km/h); a stated upper speed replaces the 5 m/s
#: (:func:`scenariominer.mine.plan_reader.read_plan`, "slow cars under 30 km/h").
SLOW = ("has_velocity", "min_velocity=0.5, max_velocity=5")
HARD_BRAKING = ("accelerating", "min_accel=-inf, max_accel=-3.0")

#: "other than X": the subject without the categories of X (:func:`scenariominer.mine.plan_reader._apply`).
EXCEPT = "except"

#: Adjectives before a road user: (pattern, condition function, argument).
MODIFIERS: tuple[tuple[str, str, str | None], ...] = (
    (r"moving|walking|running|riding|cycling", *MOVING),
    (r"parked|stationary|double[- ]parked", "stationary", None),
    (r"active|non-stationary", "not stationary", None),
    (r"jaywalking", "jaywalking", None),
    (r"stopped|halted", *STOPPED_OR_PARKED),
    (r"fast|speeding|fast-moving", "has_velocity", "min_velocity=10"),
    (r"slow|slow-moving|slowly moving", *SLOW),
    (r"turning", "turning", None),
    (r"accelerating", "accelerating", None),
    (r"hard[- ]braking|heavily braking|emergency[- ]braking", *HARD_BRAKING),
    (r"braking|decelerating", "accelerating", "min_accel=-inf, max_accel=-1.0"),
    # another road user's "oncoming": travelling against the subject (never the subject's own)
    (r"oncoming|on-coming", "oncoming", None),
)

TO_MPS = {
    "meters per second": 1.0, "metres per second": 1.0, "m/s": 1.0, "mps": 1.0,
    "kilometers per hour": 1 / 3.6, "kilometres per hour": 1 / 3.6, "km/h": 1 / 3.6, "kph": 1 / 3.6,
    "kmh": 1 / 3.6, "miles per hour": 0.44704, "mph": 0.44704,
}  # fmt: skip
#: Words that carry no condition of their own.
FILLERS = frozenset(
    {"that", "which", "who", "are", "is", "be", "being", "the", "a", "an", "any", "all", "and", "but"}
    | {"while", "also", "currently", "there", "driving", "standing"}
    | {"located", "situated", "positioned", "present", "visible", "sitting", "lying", "somewhere", "still"}
    | {"it", "they", "does", "do", "observed", "seen", "spotted", "stays", "remains", "stay", "remain"}
)


@dataclass(frozen=True)
class Phrase:
    """One phrase after the subject and what it means.

    ``{obj}`` in the pattern stands for the other road users (the phrase is then a relation to
    them); ``{name}`` in ``argument``/``direction`` is filled from the pattern's named group
    (``{speed}`` from ``value`` and ``unit``, in m/s; ``{low_speed}`` from ``low``; ``{lateral}``
    is ``lateral_thresh=1`` when a ``directly`` group matched, else nothing); a ``neg`` group
    negates a condition.
    """

    pattern: str
    function: str | None  # None: the phrase carries no condition ("in traffic")
    argument: str | None = None
    direction: str | None = None
    reverse: bool = False  # the other road users do it to the subject ("crossing in front of X")
    to_subject: bool = False  # a relation among the subject's own members ("close together")
    sides: tuple[str, ...] = ()  # one relation per direction, all required ("on both sides")
    any_side: bool = False  # with ``sides``: one relation holding in any of them ("on either side")
    implied: str | None = None  # the other road users when the phrase names none ("ahead": the ego)


_NUMBER = r"\d+(?:\.\d+)?"
_DIST = rf"(?P<dist>{_NUMBER}) ?(?:m|meters?|metres?)"
_SPEED = rf"(?P<value>{_NUMBER}) ?(?P<unit>{'|'.join(TO_MPS)})?"
_SPEED_WITH_UNIT = rf"(?P<value>{_NUMBER}) ?(?P<unit>{'|'.join(TO_MPS)})"
_GOING = r"(?:(?:moving|going|driving|travell?ing|doing) )?"
#: "with X", and "with no X" / "without X" (``no`` group: the relation must not hold)
_HAVE = r"(?:(?:(?:that|who|which) (?:have|has)|having|with)(?P<no> no)?|(?P<without>without))"
_CROSSWALK = (
    r"(?:a |the |any )?(?:marked |painted |designated )?(?:crosswalk|zebra crossing|ped(?:estrian)? crossing"
    r"|designated crossing)s?"
)
_INTERSECTION = r"(?:an |the |a )?(?:intersection|junction)s?"
_NOT = r"(?P<neg>not |without )?"
#: How many of the other road users a relation needs: "multiple X", "at least 2 X", "3 or more X".
_QUANTITY = r"(?:(?P<multi>multiple|several|many) |(?:at least )?(?P<qty>\d+) (?:or more )?)?"
#: The keyword that takes that count, per relation function.
COUNT_KEYWORD = {"has_objects_in_relative_direction": "min_number", "near_objects": "min_objects"}
_ACCEL_UNIT = r"(?:m/s2|m/s²|m/s\^2|(?:meters|metres) per second(?: squared| per second)?)"
_ACCEL = r"(?P<accel>\d+(?:\.\d+)?) ?" + _ACCEL_UNIT
_ACCEL_RANGE = r"(?P<lo>\d+(?:\.\d+)?) (?:and|to|-) (?P<hi>\d+(?:\.\d+)?) ?" + _ACCEL_UNIT
#: Not followed by a side ("within 20 m *behind them*" is a relation in that direction).
_NO_SIDE = r"(?! (?:ahead|in front|behind|in back|(?:on|to) (?:their |its |the )?(?:left|right)))"
_MORE_THAN = (
    r"(?:more than|over|faster than|harder than|stronger than|greater than|bigger than|larger than"
    r"|higher than|above|at least|exceeding"
    r"|in excess of|beyond|by more than|of more than)"
)
_LATERAL_FN = "has_lateral_acceleration"
#: not the end of "lateral acceleration" (read by its own phrases)
_NOT_SIDEWAYS = r"(?<!lateral )(?<!sideways )"
_LATERAL_ONLY = r"lateral acceleration (?:of )?" + _MORE_THAN + " " + _ACCEL
_LATERAL = r"(?:an? )?" + _LATERAL_ONLY
_SWERVE = (
    r"(?:(?:swerving|veering|weaving|jerking sideways)(?: (?:hard|sharply|suddenly|abruptly|violently))? )?"
    r"(?:(?:with|having|at|showing) )?"
)
_LEFT_ACCEL, _RIGHT_ACCEL = "min_accel={accel}", "max_accel=-{accel}"
#: "a lateral acceleration to the left above 2 m/s^2": the side named before the number
_SIDE_FIRST = r"(?:an? )?lateral acceleration (?:to(?:ward)? (?:the |its |their )?)?"
_ABOVE_ACCEL = r" (?:of )?" + _MORE_THAN + " " + _ACCEL
_SWERVING = r"(?:swerving|veering|weaving)(?: (?:hard|sharply|suddenly|abruptly|violently))?"
_TOWARD_SIDE = r"(?:to(?:ward)? (?:the |its |their )?)?"
_NEAR = r"(?:near|close to|approaching|as (?:they|it) approach(?:es)?|next to|by)"
_IN_LANE = (
    r"(?:(?:riding |driving |cycling )?(?:in|on|inside|within|using|along|through|blocking|occupying))"
    r" (?:a |the )?(?:designated |dedicated |reserved |marked )?"
)
_ON_X = "on_intersection"
_SPEEDING_UP = ("accelerating", None)
_TURNING = ("turning", "direction='{dir}'")
_BESIDE = "within_distance=5, lateral_thresh=2"
#: right beside the subject on one side: the setting has_objects_in_relative_direction's docstring
#: gives for "beside" (at most about a lane away)
_BESIDE_ONE = "within_distance=4, lateral_thresh=1"
_IT = r"(?:it|them|him|her)"
#: "ahead of X", "behind X": the predicate's defaults (50 m, no lateral limit); "directly ahead"
#: (``directly`` group) keeps to a corridor 1 m either side of X's path (``{lateral}``, see
#: :func:`scenariominer.mine.plan_reader._apply`)
_ALONG = "{lateral}"
_GET_IN_DIRECTION = "get_objects_in_relative_direction"
_DIRECTLY = r"(?P<directly>(?:directly|right|just|straight|immediately) )?"
#: "with a car (right) beside it", then optionally " on its left (side)"
_HAVE_BESIDE_IT = _HAVE + r" " + _QUANTITY + r"{obj} " + _DIRECTLY + r"(?:beside|next to|alongside) " + _IT
_ON_ITS_SIDE = r" (?:on |to )(?:their |its |his |her |the )(?P<dir>left|right)(?: side| hand side)?"
EGO = "the ego vehicle"
#: ``implied``: the road user of the last relation read (the ego when there is none)
LAST = "<last>"

#: "its", "their" or "the" before a side, or nothing.
_ITS = r"(?:its |their |the )?"
#: (not after "with", "at least" ...: "with 2 vehicles ahead" counts them)
_NOT_A_COUNT = r"(?<!with )(?<!having )(?<!has )(?<!have )(?<!least )(?<!than )(?<!most )"
_IN_LINE_AHEAD = _NOT_A_COUNT + r"(?P<rank>\d+) (?:cars?|vehicles?) (?:ahead|in front|forward)"
_IN_LINE_BEHIND = _NOT_A_COUNT + r"(?P<rank>\d+) (?:cars?|vehicles?) (?:behind|back)"

#: Phrases after the subject, tried in this order; each match is consumed.
PHRASES: tuple[Phrase, ...] = (
    # "two cars ahead (of X)": the second vehicle in line ahead of X, the ego when none is named
    Phrase(_IN_LINE_AHEAD + r" (?:of|from) {obj}", "in_line", "rank={rank}", "forward"),
    Phrase(_IN_LINE_BEHIND + r" (?:(?:of|from) )?{obj}", "in_line", "rank={rank}", "backward"),
    Phrase(_IN_LINE_AHEAD, "in_line", "rank={rank}", "forward", implied=EGO),
    Phrase(_IN_LINE_BEHIND, "in_line", "rank={rank}", "backward", implied=EGO),
    # "moving toward X with a closing speed of at least 2 m/s": the speed toward X (before the speeds of
    # the subject itself)
    Phrase(
        r"(?:heading|moving|driving|going|approaching|closing in on) (?:towards? )?{obj} (?:with|at) a"
        r" (?:closing|approach(?:ing)?) speed (?:of )?(?:at least|more than|over|above) " + _SPEED,
        "heading_toward", "minimum_speed={speed}",
    ),
    Phrase(
        r"(?:heading|moving|driving|going|approaching|closing in on) (?:towards? )?{obj} within " + _DIST
        + r" (?:with|at) a (?:closing|approach(?:ing)?) speed (?:of )?(?:at least|more than|over|above) "
        + _SPEED,
        "heading_toward", "max_distance={dist}, minimum_speed={speed}",
    ),
    # "going straight (ahead)": not turning (before the bare "ahead", a relation to the ego)
    Phrase(
        r"(?:going|driving|continuing|heading|travell?ing|moving|proceeding|riding) straight"
        r"(?: ahead| on(?! (?:an? |the )?(?:intersection|junction)))?(?! (?:at|towards?|for) )",
        "going straight",
    ),
    # a direction of travel with no one named: the ego's ("vehicles in the opposite direction")
    Phrase(
        r"(?:(?:travell?ing|heading|driving|moving|going|riding) )?in (?:the )?(?P<dir>same|opposite)"
        r" direction(?! (?:as|to|of) )",
        "heading_in_relative_direction_to", direction="{dir}", implied=EGO,
    ),
    Phrase(
        r"(?:(?:travell?ing|driving|moving|coming) )?in (?:the )?oncoming (?:lanes?|traffic)",
        "heading_in_relative_direction_to", direction="opposite", implied=EGO,
    ),
    # a cut-in closer than D ahead of X's front bumper
    Phrase(
        r"(?:cutting (?:in )?(?:in front of|ahead of)|cutting off|cutting into the path of) {obj}"
        r" within " + _DIST,
        "being_crossed_by", "forward_thresh={dist}", "forward", reverse=True,
    ),
    # a crossing closer than D ahead of X's front bumper
    Phrase(
        r"(?:crossing|walking across|running across|stepping|darting|dashing)(?: the road| the street)?"
        r" in front of {obj} within " + _DIST,
        "being_crossed_by", "forward_thresh={dist}", "forward", reverse=True,
    ),
    # stated numbers first, so "within 5 m of X" is not read as a bare relation
    Phrase(
        r"surrounded by (?P<count>\d+) or more {obj} within " + _DIST,
        "near_objects", "distance_thresh={dist}, min_objects={count}",
    ),
    Phrase(
        r"(?:with|having) (?:at least )?(?P<count>\d+)(?: or more)? {obj} within " + _DIST + _NO_SIDE,
        "near_objects", "distance_thresh={dist}, min_objects={count}",
    ),
    # "with a pedestrian within 15 m", "having multiple cyclists within 5 m" (no side named)
    Phrase(
        _HAVE + " " + _QUANTITY + r"{obj} within " + _DIST + _NO_SIDE,
        "near_objects",
        "distance_thresh={dist}",
    ),
    Phrase(r"within " + _DIST + " of " + _INTERSECTION, "near_intersection", "threshold={dist}"),
    Phrase(
        r"within " + _DIST + r" (?:ahead of|in front of) {obj}",
        "get_objects_in_relative_direction", "within_distance={dist}, {lateral}", "forward",
    ),
    Phrase(
        r"within " + _DIST + r" (?:behind|in back of) {obj}",
        "get_objects_in_relative_direction", "within_distance={dist}, {lateral}", "backward",
    ),
    Phrase(
        r"within " + _DIST + r" (?:to|on) the (?P<dir>left|right)(?: side)? of {obj}",
        "get_objects_in_relative_direction", "within_distance={dist}", "{dir}",
    ),
    Phrase(
        _DIRECTLY + r"(?:ahead of|in front of) {obj} within " + _DIST,
        "get_objects_in_relative_direction", "within_distance={dist}, {lateral}", "forward",
    ),
    Phrase(
        _DIRECTLY + r"(?:behind|in back of) {obj} within " + _DIST,
        "get_objects_in_relative_direction", "within_distance={dist}, {lateral}", "backward",
    ),
    Phrase(
        r"(?:directly )?(?:to|on) the (?P<dir>left|right)(?: side| hand side)? of {obj} within " + _DIST,
        "get_objects_in_relative_direction", "within_distance={dist}", "{dir}",
    ),
    # "with a pedestrian (directly) ahead of them within 10 m", "with 2 cyclists within 5 m behind it"
    Phrase(
        _HAVE + " " + _QUANTITY + r"{obj} " + _DIRECTLY + r"(?:ahead|in front)(?: of (?:them|it))?"
        r" within " + _DIST,
        "has_objects_in_relative_direction", "within_distance={dist}, {lateral}", "forward",
    ),
    Phrase(
        _HAVE + " " + _QUANTITY + r"{obj} within " + _DIST + r" (?:ahead|in front)(?: of (?:them|it))?",
        "has_objects_in_relative_direction", "within_distance={dist}, {lateral}", "forward",
    ),
    Phrase(
        _HAVE + " " + _QUANTITY + r"{obj} " + _DIRECTLY + r"behind(?: (?:them|it))?"
        r" within " + _DIST,
        "has_objects_in_relative_direction", "within_distance={dist}, {lateral}", "backward",
    ),
    Phrase(
        _HAVE + " " + _QUANTITY + r"{obj} within " + _DIST + r" behind(?: (?:them|it))?",
        "has_objects_in_relative_direction", "within_distance={dist}, {lateral}", "backward",
    ),
    Phrase(
        _HAVE + " " + _QUANTITY + r"{obj} " + _DIRECTLY
        + r"(?:on |to )(?:their |its |the )(?P<dir>left|right)(?: side| hand side)? within " + _DIST,
        "has_objects_in_relative_direction", "within_distance={dist}, {lateral}", "{dir}",
    ),
    Phrase(
        _HAVE + " " + _QUANTITY + r"{obj} within " + _DIST
        + r" (?:on |to )(?:their |its |the )(?P<dir>left|right)(?: side| hand side)?",
        "has_objects_in_relative_direction", "within_distance={dist}", "{dir}",
    ),
    # a place with no road user named is the ego's ("within 50 meters ahead", "to the right")
    Phrase(
        r"within " + _DIST + r" (?:ahead|in front)(?! of)",
        "get_objects_in_relative_direction", "within_distance={dist}, {lateral}", "forward",
        implied=EGO,
    ),
    Phrase(
        r"within " + _DIST + r" (?:behind|in back)(?= ,|\s*$)",
        "get_objects_in_relative_direction", "within_distance={dist}, {lateral}", "backward",
        implied=EGO,
    ),
    Phrase(
        r"within " + _DIST + r" (?:to|on) the (?P<dir>left|right)(?: side)?(?! of)",
        "get_objects_in_relative_direction", "within_distance={dist}", "{dir}", implied=EGO,
    ),
    Phrase(
        r"within " + _DIST + r" (?:on|to) either side(?! of)",
        "get_objects_in_relative_direction", "within_distance={dist}", sides=("left", "right"), any_side=True,
        implied=EGO,
    ),
    # "facing X within 30 degrees": the angle stated
    Phrase(
        r"(?:facing|pointed at|pointing at|looking at)(?: towards?)? {obj} within (?P<angle>\d+(?:\.\d+)?)"
        r" ?(?:degrees?|deg|°)",
        "facing_toward", "within_angle={angle}",
    ),
    Phrase(
        r"(?:(?:pointed|facing|pointing) (?:right |directly |straight )?(?:at|towards?)|facing) {obj}"
        r" (?:from )?(?:less than|within|under) "
        + _DIST + "(?: away)?",
        "facing_toward", "max_distance={dist}",
    ),
    Phrase(
        r"within " + _DIST + r" (?:on|to) either side of {obj}",
        "get_objects_in_relative_direction", "within_distance={dist}", sides=("left", "right"), any_side=True,
    ),
    Phrase(
        r"within " + _DIST + r" of (?:each other|one another)",
        "near_objects", "distance_thresh={dist}", to_subject=True,
    ),
    Phrase(r"within " + _DIST + " (?:of|from) {obj}", "near_objects", "distance_thresh={dist}"),
    Phrase(
        r"(?:accelerating|speeding up) (?:strongly |strong |hard |quickly )?(?:at )?" + _MORE_THAN
        + " " + _ACCEL,
        "accelerating", "min_accel={accel}",
    ),
    Phrase(_NOT_SIDEWAYS + r"(?:" + _HAVE + r" )?(?:an )?acceleration (?:of )?" + _MORE_THAN + " " + _ACCEL,
            "accelerating", "min_accel={accel}"),
    # "decelerating at between 1 and 3 m/s²": a range of the acceleration (negative when slowing)
    Phrase(r"(?:accelerating|speeding up) (?:at )?between " + _ACCEL_RANGE, "accelerating",
           "min_accel={lo}, max_accel={hi}"),
    Phrase(r"(?:decelerating|braking|slowing(?: down)?) (?:at )?between " + _ACCEL_RANGE, "accelerating",
           "min_accel=-{hi}, max_accel=-{lo}"),
    Phrase(r"(?:decelerating|braking|slowing(?: down)?) (?:at )?" + _MORE_THAN + " " + _ACCEL,
            "accelerating", "min_accel=-inf, max_accel=-{accel}"),
    Phrase(_NOT_SIDEWAYS + r"(?:" + _HAVE + r" )?(?:a )?deceleration (?:of )?" + _MORE_THAN + " " + _ACCEL,
            "accelerating", "min_accel=-inf, max_accel=-{accel}"),
    # a lateral acceleration toward one side, or of either sign ("swerving", "either way")
    Phrase(_SWERVING + " " + _TOWARD_SIDE + r"left (?:with |at )" + _LATERAL, _LATERAL_FN, _LEFT_ACCEL),
    Phrase(_SWERVING + " " + _TOWARD_SIDE + r"right (?:with |at )" + _LATERAL, _LATERAL_FN, _RIGHT_ACCEL),
    Phrase(_SWERVE + _SIDE_FIRST + "left" + _ABOVE_ACCEL, _LATERAL_FN, _LEFT_ACCEL),
    Phrase(_SWERVE + _SIDE_FIRST + "right" + _ABOVE_ACCEL, _LATERAL_FN, _RIGHT_ACCEL),
    Phrase(_SWERVE + _TOWARD_SIDE + r"(?:an? )?left(?:ward)? " + _LATERAL_ONLY, _LATERAL_FN, _LEFT_ACCEL),
    Phrase(_SWERVE + _TOWARD_SIDE + r"(?:an? )?right(?:ward)? " + _LATERAL_ONLY, _LATERAL_FN, _RIGHT_ACCEL),
    Phrase(_SWERVE + _LATERAL + r" (?:to(?:ward)? (?:the |its |their )?left|leftwards?)",
            "has_lateral_acceleration", "min_accel={accel}"),
    Phrase(_SWERVE + _LATERAL + r" (?:to(?:ward)? (?:the |its |their )?right|rightwards?)",
            "has_lateral_acceleration", "max_accel=-{accel}"),
    Phrase(_SWERVE + _LATERAL + r"(?: either way| in either direction| to either side| in any direction"
            r"| (?:to the )?left or right)?", "lateral_acceleration_either_way", "accel={accel}"),
    Phrase(_SWERVING + r"(?: sideways)? " + _TOWARD_SIDE + "left", "swerving left"),
    Phrase(_SWERVING + r"(?: sideways)? " + _TOWARD_SIDE + "right", "swerving right"),
    Phrase(_SWERVING + r"(?: sideways| from side to side| across (?:the )?lanes?)?", "swerving"),
    Phrase(
        _GOING + r"(?:at )?(?:a )?(?:speeds? )?(?:of )?between (?P<low>" + _NUMBER + r") ?(?:"
        + "|".join(TO_MPS) + r")? and " + _SPEED,
        "has_velocity", "min_velocity={low_speed}, max_velocity={speed}",
    ),
    Phrase(
        _GOING + r"(?:at |with )?(?:an? )?(?:speeds?|velocit(?:y|ies)) (?:of )?(?:more than|over|above"
        r"|higher than|greater than|exceeding|in excess of|at least) " + _SPEED,
        "has_velocity", "min_velocity={speed}",
    ),
    Phrase(
        _GOING + r"(?:at |with )?(?:an? )?(?:speeds?|velocit(?:y|ies)) (?:of )?(?:less than|below|under"
        r"|lower than|at most) " + _SPEED,
        "has_velocity", "max_velocity={speed}",
    ),
    Phrase(
        _GOING + r"(?:faster than|above|over|at more than|exceeding|at over) " + _SPEED,
        "has_velocity", "min_velocity={speed}",
    ),
    # "doing more than 10 mph": a speed, since the unit says so
    Phrase(
        r"(?:moving|going|driving|travell?ing|doing) (?:more than|at least) " + _SPEED_WITH_UNIT,
        "has_velocity", "min_velocity={speed}",
    ),
    Phrase(
        _GOING + r"(?:slower than|below|under|at less than) " + _SPEED,
        "has_velocity", "max_velocity={speed}",
    ),
    # relations to other road users
    Phrase(
        r"(?:crossing|walking across|running across|passing|walking|running|stepping|darting|dashing)"
        r"(?: the road| the street)? in front of {obj}",
        "being_crossed_by", direction="forward", reverse=True,
    ),
    Phrase(
        r"(?:with|having) {obj} (?:walking |running |cycling )?(?:crossing|across) in front of (?:them|it)",
        "being_crossed_by", direction="forward",
    ),
    # ... from its left to its right: clockwise seen from above
    Phrase(r"being crossed (?:in front )?from " + _ITS + r"left to " + _ITS + r"right by {obj}",
           "being_crossed_by", "in_direction='clockwise'", "forward"),
    Phrase(r"being crossed (?:in front )?from " + _ITS + r"right to " + _ITS + r"left by {obj}",
           "being_crossed_by", "in_direction='counterclockwise'", "forward"),
    Phrase(r"(?:being )?crossed (?:in front )?by {obj} (?:walking |running |moving |going |cycling )?from "
           + _ITS + r"left to " + _ITS + r"right(?: in front(?: of (?:it|them))?)?",
           "being_crossed_by", "in_direction='clockwise'", "forward"),
    Phrase(r"(?:being )?crossed (?:in front )?by {obj} (?:walking |running |moving |going |cycling )?from "
           + _ITS + r"right to " + _ITS + r"left(?: in front(?: of (?:it|them))?)?",
           "being_crossed_by", "in_direction='counterclockwise'", "forward"),
    # ... on one side: the other road user crosses the line of its left or right side
    Phrase(r"being crossed (?:on|at|from) (?:the|its|their) (?P<dir>left|right)(?: side)? by {obj}",
           "being_crossed_by", direction="{dir}"),
    Phrase(r"being crossed by {obj} (?:on|at|from) (?:the|its|their) (?P<dir>left|right)(?: side)?",
           "being_crossed_by", direction="{dir}"),
    Phrase(r"being crossed by {obj}", "being_crossed_by", direction="forward"),
    # ... behind it: the other road user crosses the line of its rear bumper
    Phrase(
        r"(?:(?:crossing|walking across|running across|darting|dashing)(?: the road| the street)?"
        r" (?:behind|at the (?:back|rear) of)"
        r"|(?:crossing|walking|running|passing|stepping|darting|dashing) across the (?:back|rear) of) {obj}",
        "being_crossed_by", direction="backward", reverse=True,
    ),
    Phrase(
        r"(?:with|having) {obj} (?:walking |running |cycling )?(?:crossing|across)"
        r" (?:behind|at the (?:back|rear) of) (?:them|it)",
        "being_crossed_by", direction="backward",
    ),
    Phrase(r"being crossed (?:from behind|behind|at the (?:back|rear)) by {obj}", "being_crossed_by",
           direction="backward"),
    # "with a vehicle heading toward them": the other road user moves toward the subject
    Phrase(
        _HAVE + r" {obj} (?:heading|moving|driving|coming|going|walking|riding) (?:straight |directly )?"
        r"(?:towards?|at) (?:them|it) within " + _DIST,
        "heading_toward", "max_distance={dist}", reverse=True,
    ),
    Phrase(
        _HAVE + r" {obj} (?:heading|moving|driving|coming|going|walking|riding) (?:straight |directly )?"
        r"(?:towards?|at) (?:them|it)",
        "heading_toward", reverse=True,
    ),
    # "with the ego vehicle facing them": the other road user faces the subject
    Phrase(
        _HAVE + r" {obj} (?:facing|pointing|pointed|looking|aimed|aiming) (?:straight |directly |right )?"
        r"(?:towards?|at)? ?(?:them|it) within " + _DIST,
        "facing_toward", "max_distance={dist}", reverse=True,
    ),
    Phrase(
        _HAVE + r" {obj} (?:facing|pointing|pointed|looking|aimed|aiming) (?:straight |directly |right )?"
        r"(?:towards?|at)? ?(?:them|it)",
        "facing_toward", reverse=True,
    ),
    # a cut-in: the other road user crosses the line straight ahead of X's front bumper
    Phrase(
        r"(?:cutting (?:in )?(?:in front of|ahead of)|cutting off|cutting into the path of) {obj}",
        "being_crossed_by", direction="forward", reverse=True,
    ),
    Phrase(
        _HAVE + r" {obj} (?:walking |running |cycling |driving )?(?:crossing|cutting across)"
        r" (?:their|its) path(?: in front(?: of (?:them|it))?)?",
        "being_crossed_by", direction="forward",
    ),
    # overtaking: the overtaker crosses the other's left side from behind to ahead (clockwise)
    Phrase(r"(?:overtaking|passing) {obj} on the right", "being_crossed_by",
            "in_direction='counterclockwise', forward_thresh=4", "right", reverse=True),
    Phrase(r"(?:overtaking|passing) {obj}(?: on (?:the|its|their) left(?: side| hand side)?)?",
            "being_crossed_by",
            "in_direction='clockwise', forward_thresh=4", "left", reverse=True),
    Phrase(r"(?:being |getting )?(?:overtaken|passed) on (?:the|their|its) right(?: side)? by {obj}",
           "being_crossed_by",
            "in_direction='counterclockwise', forward_thresh=4", "right"),
    Phrase(r"(?:being |getting )?(?:overtaken|passed) by {obj} on the right", "being_crossed_by",
            "in_direction='counterclockwise', forward_thresh=4", "right"),
    Phrase(r"(?:being |getting )?(?:overtaken|passed) (?:on (?:the|their|its) left(?: side)? )?by {obj}"
           r"(?: on the left)?",
           "being_crossed_by",
            "in_direction='clockwise', forward_thresh=4", "left"),
    # ... by a vehicle, when the overtaker is not named
    Phrase(r"(?:being |getting )?(?:overtaken|passed) (?:on|from) (?:the )?right", "being_crossed_by",
            "in_direction='counterclockwise', forward_thresh=4", "right", implied="vehicles"),
    Phrase(r"(?:being |getting )(?:overtaken|passed)(?: (?:on|from) (?:the )?left)?", "being_crossed_by",
            "in_direction='clockwise', forward_thresh=4", "left", implied="vehicles"),
    Phrase(r"(?:following|tailgating|tailing|trailing|hanging back behind|lagging behind|following behind"
           r"|(?:driving |travell?ing )?closely behind) {obj}"
            r" in (?:the )?same lane",
            "following"),
    Phrase(r"(?:following|tailgating|tailing|trailing|hanging back behind|lagging behind|following behind"
           r"|(?:following |driving |riding |travell?ing )?closely behind"
            r"|(?:following |driving )?too close(?:ly)? behind|driving behind) {obj}"
            r"(?: too closely| closely)?", "following"),
    Phrase(r"being (?:followed|tailgated) by {obj}", "following", reverse=True),
    Phrase(r"(?:(?:in|sharing) (?:the )?same lane as|sharing (?:a |the )?lane with) {obj}", "in_same_lane"),
    Phrase(
        r"(?:heading|moving|driving|going|walking|running|riding|travell?ing|cycling|approaching"
        r"|closing in on) (?:straight |directly )?(?:towards? )?{obj} within " + _DIST + "(?: away)?",
        "heading_toward", "max_distance={dist}",
    ),
    Phrase(r"(?:approaching|closing in on) {obj}", "heading_toward"),
    # "moving toward X" states no distance: the predicate's own (any distance)
    Phrase(
        r"(?:heading|moving|driving|going|walking|running|riding|travell?ing|cycling)"
        r" (?:straight |directly )?towards? {obj}",
        "heading_toward",
    ),
    Phrase(
        r"(?:(?:directly )?facing(?: towards?)?|looking (?:straight |directly |right )?(?:towards?|at)"
        r"|turned towards?"
        r"|(?:pointed|pointing|aimed|aiming) (?:directly |straight |right )?(?:at|towards?)) {obj}",
        "facing_toward",
    ),
    Phrase(
        r"on the (?:other|opposite) side of the road(?: from| to| than| relative to| with respect to)? {obj}",
        "on_relative_side_of_road", "side='opposite'",
    ),
    Phrase(r"on the same side of the road as {obj}", "on_relative_side_of_road", "side='same'"),
    Phrase(
        r"(?:travell?ing|heading|driving|moving|going|riding) (?:in (?:the )?)?"
        r"(?P<dir>same|opposite)(?: direction)? (?:as|to|of) {obj}",
        "heading_in_relative_direction_to", direction="{dir}",
    ),
    # "walking in the same direction as X": the walking is read on its own (moving)
    Phrase(
        r"in (?:the )?(?P<dir>same|opposite) direction (?:as|to|of) {obj}",
        "heading_in_relative_direction_to", direction="{dir}",
    ),
    # "... as it": the road user named last
    Phrase(
        r"(?:(?:travell?ing|heading|driving|moving|going|riding) )?in (?:the )?(?P<dir>same|opposite)"
        r" direction (?:as|to|of) (?:it|them)",
        "heading_in_relative_direction_to", direction="{dir}", implied=LAST,
    ),
    Phrase(
        r"(?:(?:travell?ing|heading|driving|moving|going|riding) )?(?:perpendicular|at (?:a )?right angles?)"
        r" to {obj}",
        "heading_in_relative_direction_to", direction="perpendicular",
    ),
    Phrase(
        _HAVE + r" " + _QUANTITY + r"{obj} (?:(?:on |to )(?:both )?(?:their |its |the )?left and right"
        r"|on both (?:their |its )?sides)",
        "has_objects_in_relative_direction", _BESIDE, sides=("left", "right"),
    ),
    Phrase(
        r"(?:surrounded|boxed in|hemmed in) by {obj} on all (?:four )?sides",
        "has_objects_in_relative_direction", _BESIDE, sides=("left", "right", "forward", "backward"),
    ),
    Phrase(
        r"(?:boxed|hemmed|squeezed) in by {obj} (?:(?:on |to )(?:both )?(?:their |its |the )?left and right"
        r"|on both (?:their |its )?sides)",
        "has_objects_in_relative_direction", _BESIDE, sides=("left", "right"),
    ),
    # "between two parked cars": one on the subject's left and one on its right, relative to the
    # subject's own heading (a pedestrian crossing through a gap has the cars to its sides)
    Phrase(
        r"(?:passing |crossing |walking |riding |driving |squeezing )?(?:in )?between (?:2 )?{obj}",
        "has_objects_in_relative_direction", _BESIDE, sides=("left", "right"),
    ),
    Phrase(
        _HAVE + r" " + _QUANTITY
        + r"{obj} (?:on |to )(?:their |its |the )(?P<dir>left|right)(?: side| hand side)?",
        "has_objects_in_relative_direction", None, "{dir}",
    ),
    # "with a car (right) beside it on the left": that side, close ("beside it": either side); a
    # stated distance says how close
    Phrase(_HAVE_BESIDE_IT + _ON_ITS_SIDE + r" within " + _DIST, "has_objects_in_relative_direction",
            "within_distance={dist}", "{dir}"),
    Phrase(_HAVE_BESIDE_IT + _ON_ITS_SIDE, "has_objects_in_relative_direction", _BESIDE_ONE, "{dir}"),
    Phrase(_HAVE_BESIDE_IT, "has_objects_in_relative_direction", _BESIDE_ONE, sides=("left", "right"),
            any_side=True),
    # "a vehicle that has another vehicle following it": the one followed
    Phrase(
        _HAVE + r" " + _QUANTITY + r"{obj} (?:following|tailgating|trailing)(?: closely)?(?: behind)? " + _IT,
        "following",
        reverse=True,
    ),
    Phrase(
        _HAVE + r" " + _QUANTITY + r"{obj} (?:on |to )either side",
        "has_objects_in_relative_direction", sides=("left", "right"), any_side=True,
    ),
    Phrase(_HAVE + r" " + _QUANTITY + r"{obj} " + _DIRECTLY + r"behind(?: them| it)?",
            "has_objects_in_relative_direction",
            _ALONG, "backward"),
    Phrase(
        _HAVE + r" " + _QUANTITY + r"{obj} " + _DIRECTLY + r"(?:in front|ahead)(?: of (?:them|it))?",
        "has_objects_in_relative_direction", _ALONG, "forward",
    ),
    Phrase(
        r"(?:towing|pulling) {obj}",
        "has_objects_in_relative_direction", "within_distance=2, lateral_thresh=0.5", "backward",
    ),
    Phrase(_DIRECTLY + r"(?:behind|in back of) {obj}", _GET_IN_DIRECTION, _ALONG, "backward"),
    Phrase(_DIRECTLY + r"(?:ahead of|in front of) {obj}", _GET_IN_DIRECTION, _ALONG, "forward"),
    Phrase(
        r"(?:crossing|walking across|running across)(?: the road| the street)? (?:ahead|in front)(?! of)",
        "being_crossed_by", direction="forward", reverse=True, implied=EGO,
    ),
    Phrase(_DIRECTLY + r"ahead(?! of)", "get_objects_in_relative_direction", _ALONG, "forward",
            implied=EGO),
    Phrase(
        r"(?:directly |immediately )?(?:to|on) either side of {obj}",
        "get_objects_in_relative_direction", sides=("left", "right"), any_side=True,
    ),
    Phrase(
        r"(?:directly |immediately )?(?:to|on) (?:the )?(?P<dir>left|right)(?: side| hand side)? of {obj}",
        "get_objects_in_relative_direction", None, "{dir}",
    ),
    Phrase(r"(?:pushed|pulled|walked|carried) by {obj}", "near_objects", "distance_thresh=1"),
    Phrase(r"(?:with|having) " + _QUANTITY + r"nearby {obj}", "near_objects", "distance_thresh=10"),
    # in X's path: ahead of X, within its width (1 m either side of its centre line)
    Phrase(r"in (?:the )?path of {obj} within " + _DIST, "get_objects_in_relative_direction",
            "within_distance={dist}, lateral_thresh=1", "forward"),
    Phrase(r"in (?:the )?path of {obj}", "get_objects_in_relative_direction", "lateral_thresh=1", "forward"),
    Phrase(r"(?:with|having) " + _QUANTITY + r"{obj} (?:nearby|close by|around)", "near_objects",
            "distance_thresh=10"),
    Phrase(
        r"(?:walking |moving |standing |riding )?(?:close together|side by side|in a group|together"
        r"|(?:near|close to|next to) (?:each other|one another))",
        "near_objects", "distance_thresh=2", to_subject=True,
    ),
    Phrase(r"(?:going|driving|passing) close by {obj}", "near_objects", "distance_thresh=5"),
    Phrase(r"(?:going past|driving past|passing by) {obj}", "near_objects", "distance_thresh=20"),
    # places on the map (before the bare "near X", which would read "an intersection" as a road user)
    Phrase(
        _NOT + _IN_LANE + r"(?:bike|bicycle|cycle)(?:[- ]only)? lanes?",
        "on_lane_type", "lane_type='BIKE'",
    ),
    Phrase(_NOT + _IN_LANE + r"bus(?:[- ]only)? lanes?", "on_lane_type", "lane_type='BUS'"),
    Phrase(
        _NOT + _IN_LANE + r"(?:(?:regular|normal|general|ordinary) )?(?:vehicle|car|traffic|driving) lanes?",
        "on_lane_type", "lane_type='VEHICLE'",
    ),
    # a parking lot or a driveway: drivable, but no road
    Phrase(
        r"(?:in|on|at|inside|within) (?:a |the )?(?:parking (?:lot|area|garage)|car park|driveway)s?"
        r"(?: or (?:a |the )?(?:parking (?:lot|area|garage)|car park|driveway)s?)?",
        "parking lot",
    ),
    Phrase(
        r"(?P<neg>more than) " + _DIST + r" (?:away )?from (?:any |an |the |a )?(?:intersection|junction)s?",
        "near_intersection", "threshold={dist}",
    ),
    Phrase(r"(?P<neg>not (?:near|close to|at)|away from|far from) " + _INTERSECTION, "near_intersection"),
    Phrase(_NEAR + " " + _INTERSECTION + " within " + _DIST, "near_intersection", "threshold={dist}"),
    Phrase(_NEAR + " " + _INTERSECTION, "near_intersection"),
    Phrase(
        r"(?P<neg>(?:but )?(?:outside|not in|not inside|not on))(?: of)?(?: it| " + _INTERSECTION + ")", _ON_X
    ),
    Phrase(r"(?:in|on|inside|within|through|crossing|across|over|in the middle of) " + _INTERSECTION, _ON_X),
    # "at an intersection": on it or just before it (stopped at the stop line, turning there)
    Phrase(r"at " + _INTERSECTION, "near_intersection"),
    Phrase(_NEAR + " " + _CROSSWALK + " within " + _DIST, "at_pedestrian_crossing", "within_distance={dist}"),
    Phrase(r"(?P<neg>not )?within " + _DIST + " of " + _CROSSWALK, "at_pedestrian_crossing",
           "within_distance={dist}"),
    Phrase(_NEAR + " " + _CROSSWALK, "at_pedestrian_crossing", "within_distance=5"),
    Phrase(r"(?P<neg>away from|not at|not on|not using|without using|outside(?: of)?) " + _CROSSWALK,
            "at_pedestrian_crossing"),
    # "walking across a crosswalk": at it (the predicate's default) and moving
    Phrase(
        r"(?:crossing|(?:walking |running |riding )?(?<!driving )(?<!going )across) " + _CROSSWALK,
        "crossing at crosswalk",
    ),
    Phrase(r"(?:on|in|inside|within|(?:driving|going) across) " + _CROSSWALK,
            "at_pedestrian_crossing", "within_distance=0"),
    Phrase(r"(?:at|using) " + _CROSSWALK, "at_pedestrian_crossing"),
    Phrase(r"(?:at|near|approaching) (?:a |the )?stop signs?", "at_stop_sign"),
    Phrase(r"(?P<neg>off (?:the |a )?(?:road|street)|not on (?:the |a )?(?:road|street))", "on_road"),
    Phrase(
        r"(?P<neg>outside|off|not (?:on|in|inside|within)) the drivable (?:area|surface|space|region)",
        "in_drivable_area",
    ),
    Phrase(
        r"(?:(?:placed|located|sitting|lying|left|standing|positioned|situated) )?(?:on|in|within|inside)"
        r" the drivable (?:area|surface|space|region|road surface)",
        "in_drivable_area",
    ),
    Phrase(r"(?P<neg>on|along) the (?:sidewalk|pavement|footway|footpath)", "in_drivable_area"),
    Phrase(r"(?:on|in) (?:the |a )?(?:road|street|roadway|carriageway)", "on_road"),
    # "in a lane" of no named type: on the road (the lanes are the road)
    Phrase(
        r"(?:in|on|inside|within|blocking) (?:a |the )?(?:travel |traffic )?lanes?(?! (?:as|of|with))",
        "on_road",
    ),
    Phrase(r"in traffic", None),
    # the logs' own frame: "buses *driving through the scene*" (moving), "cars *in the scene*"
    Phrase(
        r"(?:driving|moving|passing|going|travell?ing|riding|walking) (?:through|across)"
        r" the (?:scene|frame|view)",
        *MOVING,
    ),
    Phrase(r"(?:in|within|across|throughout) the (?:scene|frame|view|log|logs|recording|data)", None),
    # "other than X", "except X", "that are not X": the subject without X's categories
    Phrase(r"(?:other than|except(?: for)?|excluding|apart from|but not|not) {obj}", EXCEPT),
    # "ahead of the ego in the same lane": the lane of the road user the description last named
    Phrase(r"in (?:the )?same lane(?! as)", "in_same_lane", implied=LAST),
    Phrase(r"on the same side of the road(?! as)", "on_relative_side_of_road", "side='same'", implied=LAST),
    Phrase(
        r"on the (?:other|opposite) side of the road(?! from| to| than)",
        "on_relative_side_of_road", "side='opposite'", implied=LAST,
    ),
    Phrase(r"jaywalking", "jaywalking"),
    # "crossing the street" with no one named: on the road and moving (a crossing in front of
    # someone, of an intersection or of a crosswalk is read above)
    Phrase(
        r"(?:crossing|walking across|running across)(?: (?:the |a )?(?:road|street|roadway))?", "crossing"
    ),
    # "right next to X on its right side": beside X, on that side (within a stated distance)
    Phrase(
        _DIRECTLY + r"(?:next to|beside|alongside) {obj} (?:on|to) (?:its|their|the) (?P<dir>left|right)"
        r"(?: side| hand side)? within " + _DIST,
        _GET_IN_DIRECTION, "within_distance={dist}", "{dir}",
    ),
    Phrase(
        _DIRECTLY + r"(?:next to|beside|alongside) {obj} (?:on|to) (?:its|their|the) (?P<dir>left|right)"
        r"(?: side| hand side)?",
        _GET_IN_DIRECTION, _BESIDE_ONE, "{dir}",
    ),
    # "..., no more than 20 m away" at the end (after every phrase that takes a distance): from
    # the road user named last
    Phrase(
        r"within " + _DIST + r"(?: away)?(?= ,|\s*$)", "near_objects", "distance_thresh={dist}", implied=LAST
    ),
    # bare relations (after the map phrases)
    Phrase(r"(?:near|next to|beside|alongside|nearby|around) " + _QUANTITY + "{obj}", "near_objects",
            "distance_thresh=10"),
    # "close to X" states no distance: the predicate's default, as "near" (two independent reference
    # writers took it so); "very close to" says how close
    Phrase(r"(?:very close to|in close proximity to|right up against) " + _QUANTITY + "{obj}", "near_objects",
            "distance_thresh=5"),
    Phrase(r"(?:close to|close by) " + _QUANTITY + "{obj}", "near_objects", "distance_thresh=10"),
    # motions of the subject
    Phrase(
        r"(?:slamming on the brakes|braking hard|braking heavily|hard braking|heavy braking|emergency braking"
        r"|stopping suddenly|decelerating hard)",
        *HARD_BRAKING,
    ),
    Phrase(_NOT + r"(?:speeding up|accelerating|picking up speed|gaining speed)", *_SPEEDING_UP),
    Phrase(
        r"(?:hitting|applying|pressing|tapping|stepping on|using|on) (?:the |their |its )?brakes?",
        "accelerating", "min_accel=-inf, max_accel=-1.0",
    ),
    Phrase(
        _NOT + r"(?:slowing down|slowing|decelerating|braking|losing speed)",
        "accelerating", "min_accel=-inf, max_accel=-1.0",
    ),
    Phrase(
        r"(?:pulling away|pulling out|taking off|setting off|starting (?:to move|off|up))"
        r"(?: from (?:a |the )?(?:stop|standstill|curb|kerb))?",
        *_SPEEDING_UP,
    ),
    Phrase(
        r"(?:(?:has |have |had )?(?:come|coming|came) to an? (?:momentary |brief |short |temporary |full )?"
        r"(?:stop|halt)|stopping|(?:momentarily|briefly|temporarily) (?:stopped|halted|stopping)"
        r"|(?:making|at) an? (?:momentary|brief|short|temporary) stop)",
        *STOPPED,
    ),
    Phrase(r"(?:making|taking|doing|performing) an? (?P<dir>left|right)(?: turn| hand turn)?", *_TURNING),
    Phrase(r"(?:(?:making|taking|doing|performing|executing) an? u-?turn|u-?turning)", "turning"),
    Phrase(r"turning (?:to the )?(?P<dir>left|right)", *_TURNING),
    Phrase(_NOT + r"(?:making a turn|turning)", "turning"),
    Phrase(
        r"(?:changing lanes?|switching lanes?|moving over|merging) (?:in)?to the (?P<dir>left|right)",
        "changing_lanes", "direction='{dir}'",
    ),
    Phrase(
        r"(?:changing(?: lanes?)?|switching(?: lanes?)?|moving over|merging|moving) into the lane"
        r" (?:on |to )(?:their |its |the )(?P<dir>left|right)",
        "changing_lanes", "direction='{dir}'",
    ),
    Phrase(
        r"(?:making|performing|doing) a lane change (?:in)?to the (?P<dir>left|right)",
        "changing_lanes", "direction='{dir}'",
    ),
    Phrase(
        r"(?:making|performing|doing) an? (?P<dir>left|right) lane change",
        "changing_lanes", "direction='{dir}'",
    ),
    Phrase(
        _NOT + r"(?:changing lanes?|switching lanes?|lane changing"
        r"|(?:performing|making|doing) a lane change)",
        "changing_lanes",
    ),
    Phrase(r"(?:waiting )?(?:stopped|halted)", *STOPPED_OR_PARKED),
    # at rest at the timestamp, parked objects included (as "stopped")
    # waiting: momentarily stopped, not parked
    Phrase(
        r"(?:waiting|momentarily|briefly|temporarily) (?:standing still|at a standstill|not moving|at rest)",
        *STOPPED,
    ),
    Phrase(r"(?:standing still|at a standstill|not moving|at rest)", *STOPPED_OR_PARKED),
    # "waiting at a stop sign": stopped there (the place is read by its own phrase)
    Phrase(r"waiting", *STOPPED),
    Phrase(_NOT + r"(?:double[- ]parked|parked|stationary)", "stationary"),
    # "who stay in 1 spot for the whole log": stationary (the predicate's own sense)
    Phrase(
        r"(?:stays?|staying|remains?|remaining) (?:(?:in|at) (?:1|the same|same) (?:spot|place|position"
        r"|location)|still|stationary|in place|put)(?: (?:for |during |throughout )?(?:all )?the"
        r" (?:whole |entire )?(?:log|scene|recording|time))?",
        "stationary",
    ),
    Phrase(r"(?:that )?(?:has not|hasn't|have not|haven't|never) moved", "stationary"),
    Phrase(r"(?:moving )?(?:at (?:a )?crawling speed|crawling|creeping)(?: along| forward)?", "has_velocity",
            "min_velocity=0.5, max_velocity=3"),
    Phrase(r"(?:(?:moving |driving |going |travell?ing )?(?:at (?:a )?high speed|quickly|fast|rapidly))",
            "has_velocity", "min_velocity=10"),
    Phrase(
        r"(?:(?:moving |driving |going |travell?ing |walking |riding )?(?:slowly|slow|at (?:a )?low speed))",
        *SLOW,
    ),
    Phrase(r"(?:moving|in motion|walking|riding|cycling|jogging|running|travell?ing)", *MOVING),
)  # fmt: skip
