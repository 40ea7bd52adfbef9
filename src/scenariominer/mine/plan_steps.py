"""A step-by-step procedure, put in the one phrase the phrase rules read.

Some users write a search the way they would build it by hand, as numbered steps: "1. Take all
pedestrians. 2. Throw out the ones inside the drivable area. 3. Whatever is left is the set."
:func:`procedure_wording` follows the steps: a step that takes a set ("take all buses", "get the
ego vehicle") names a road user, the first of them the one found; a step that keeps some ("keep
only the ones on the road", "keep the moments they move at 5 m/s or more") adds a condition, and
one that drops some ("throw out", "drop", "leave out") adds its negation; "keep the bicycles with a
vehicle within 5 m of them" makes the bicycles the ones found (the vehicles are named in the
condition itself), and "merge the two groups" finds either of the last two sets. Steps that only
end the procedure ("done", "output them", "that is the set") say nothing. The result is one phrase:
"pedestrians not inside the drivable area". Text that is not such a procedure, or one with a step
this reading does not know, comes back unchanged.
"""

from __future__ import annotations

import re

from scenariominer.mine.plan_nouns import NOUN, singular

__all__ = ["procedure_wording"]

#: A step's number: "1.", "2)", "Step 3:".
_STEP = re.compile(r"(?:^|(?<=[\s.;]))(?:step\s*)?(?P<n>\d{1,2})\s*[.):]\s+", re.IGNORECASE)
_TAKE = re.compile(
    r"^(?:first,? )?(?:take|get|collect|start (?:with|from)|gather|grab|select|pick|find|list|load|fetch)"
    r"(?: out)? (?:all |every |each |the |all the )*(?P<set>.+?)(?: in the (?:log|scene|data|recording))?$"
)
_FROM_THEM = r"(?:(?:from|of|among|out of) (?:them|these|those|that set|the rest),? )?(?:then )?"
_KEEP = re.compile(rf"^{_FROM_THEM}(?:keep|retain|take|select|filter(?: to)?|find)(?: only)? (?P<rest>.+)$")
_DROP = re.compile(
    rf"^{_FROM_THEM}(?:throw out|drop|remove|discard|exclude|leave out|filter out|take out|get rid of|delete)"
    r" (?P<rest>.+)$"
)
_MERGE = re.compile(r"^(?:merge|combine|join|union|put together|pool)\b")
_END = re.compile(
    r"^(?:done|finish(?:ed)?|end|stop(?: there| here)?|that(?:'s| is) (?:the|your|our) (?:set|answer|result)"
    r"|(?:whatever|what) (?:is|remains) (?:left )?(?:is )?(?:the )?(?:set|answer|result)?"
    r"|the rest\b.*|output\b.*|return\b.*|report\b.*|show\b.*|these are\b.*|this is\b.*|those are\b.*"
    r"|.*\bboth (?:hold|apply|are true)\b.*)$"
)
#: The words that point back at the set being built ("the ones", "those", "the moments they are").
_THEM = re.compile(
    r"^(?:(?:only )?(?:the ones|ones|those|them|these|the rest)"
    r"|(?:at )?(?:the |those )?(?:moments?|times?|frames?|timestamps?|instants?)"
    r"(?: (?:when|where|that|in which|at which|of|with))?)\b\s*"
)
#: "the moving ones": the word before "ones" is the condition.
_ONES = re.compile(r"^(?:the |those )?(?P<mods>[\w-]+(?: [\w-]+)?) ones\b\s*(?P<cond>.*)$")
#: Words before a set's noun that only point back at it ("the remaining vehicles").
_BACK = frozenset({"remaining", "rest", "other", "leftover", "surviving", "selected", "same"})


class _Unknown(Exception):
    """A step this reading does not follow."""


def procedure_wording(description: str) -> str:
    """``description`` as one phrase when it is a numbered procedure, else unchanged."""
    marks = list(_STEP.finditer(description))
    if (
        len(marks) < 2
        or marks[0].start() > 0
        or [int(m["n"]) for m in marks] != list(range(1, len(marks) + 1))
    ):
        return description
    steps = [
        description[m.end() : (marks[i + 1].start() if i + 1 < len(marks) else len(description))]
        for i, m in enumerate(marks)
    ]
    try:
        return _follow([" ".join(s.lower().split()).strip(" .;") for s in steps])
    except _Unknown:
        return description


def _follow(steps: list[str]) -> str:
    """The phrase the steps build: the set found and its conditions."""
    sets: list[str] = []
    subject: str | None = None
    conditions: list[str] = []
    for step in steps:
        # "take all vehicles and keep the moving ones": two steps in one; "stop there; that is the set"
        parts = re.split(r";\s*|,? (?:and|then) (?=(?:keep|drop|throw out|remove|exclude|leave out)\b)", step)
        taken_other = False  # this step took a set other than the one found: its keeps are that set's
        for part in (p.strip(" .,") for p in parts):
            if not part or _END.match(part):
                continue
            if _MERGE.match(part):
                if len(sets) < 2:
                    raise _Unknown(part)
                subject, conditions = f"{sets[-2]} or {sets[-1]}", []
            elif (taken := _TAKE.match(part)) and re.match(rf"(?:{NOUN})\b", taken["set"]):
                sets.append(re.sub(r",? of any (?:category|kind|type|class)\b", " of any kind", taken["set"]))
                taken_other = subject is not None
                subject = subject or sets[-1]
            elif taken_other and (_KEEP.match(part) or _DROP.match(part)):
                continue  # "take all vehicles and keep the moving ones": restated where they are used
            elif (kept := _KEEP.match(part)) is not None and subject is not None:
                subject, conditions = _keep(kept["rest"], subject, conditions, negated=False)
            elif (dropped := _DROP.match(part)) is not None and subject is not None:
                subject, conditions = _keep(dropped["rest"], subject, conditions, negated=True)
            else:
                raise _Unknown(part)
    if subject is None:
        raise _Unknown("no set taken")
    return " ".join([subject, " and ".join(conditions)]).strip()


def _keep(rest: str, subject: str, conditions: list[str], *, negated: bool) -> tuple[str, list[str]]:
    """A keep (or drop) step: the set it keeps and the conditions so far."""
    named = re.match(
        rf"^(?:the |those |all )?(?P<mods>(?:[\w-]+ ){{0,2}}?)(?P<noun>{NOUN})\b\s*(?P<cond>.*)$", rest
    )
    ones = _ONES.match(rest)
    if named is not None and not _THEM.match(rest):
        noun = named["noun"]
        mods = " ".join(w for w in named["mods"].split() if w not in _BACK)
        if _same_kind(noun, subject):
            # "keep the moving vehicles (over 0.5 m/s)": a condition on the same set, once
            said = mods if mods and mods not in conditions else ""
            return subject, [
                *conditions,
                *_condition(said, negated=negated),
                *_condition(_THEM.sub("", named["cond"], count=1), negated=negated),
            ]
        elif (
            negated and not named["cond"].strip(" ,") or re.fullmatch(r"from (?:them|the set)", named["cond"])
        ):
            # "drop the ego vehicle (from them)": the set without that kind
            return f"{subject} except the {noun}", conditions
        else:
            # "keep the bicycles with a vehicle within 5 m of them": those are the ones found
            subject, conditions, condition = noun, [], named["cond"]
    elif ones is not None and ones["mods"] not in ("the", "those"):
        # "the stopped ones: those parked ... plus those ...": the word says it, the rest defines it
        condition = " ".join([ones["mods"], re.sub(r"^\s*:.*$", "", ones["cond"])])
    else:
        condition = _THEM.sub("", rest, count=1)
    return subject, [*conditions, *_condition(condition, negated=negated)]


def _condition(condition: str, *, negated: bool) -> list[str]:
    """A step's condition in the words the phrase rules read (empty when it says nothing)."""
    condition = condition.strip(" ,")
    condition = re.sub(r"^(?:they|it) (?:are|is) ", "", condition)
    condition = re.sub(r"^(?:they|it) (?=\w)", "that ", condition)
    condition = re.sub(r"^(?:their|its) ", "with ", condition)
    condition = re.sub(r"^(?:that|which) (?:are|is) ", "", condition)
    condition = re.sub(
        r"^whose (?:box|bounding box|centre|center|footprint|cuboid) (?:overlaps|is on|is in|lies (?:on|in)"
        r"|touches|is inside)",
        "on",
        condition,
    )
    condition = re.sub(
        r"\b(?:is|are) (\d+(?:\.\d+)? ?\S+) or (?:more|higher|above|greater)\b", r"of at least \1", condition
    )
    condition = re.sub(
        r"\b(?:is|are) (\d+(?:\.\d+)? ?\S+) or (?:less|lower|below|fewer)\b", r"of at most \1", condition
    )
    condition = re.sub(r"\s+of (?:them|it)$", "", condition).strip(" ,")
    # "..., leaving out buses parked for the whole log": and not parked
    condition = re.sub(
        rf",? (?:leaving out|excluding|but not|except(?: for)?) (?:the |any )?(?:(?:{NOUN}) )?",
        " and not ",
        condition,
    )
    if not condition:
        return []
    if negated:
        with_any = re.match(r"^with (?:any|an?) (?P<rest>.+)$", condition)
        return [f"with no {with_any['rest']}" if with_any else f"not {condition}"]
    return [condition]


def _same_kind(noun: str, subject: str) -> bool:
    """Whether ``noun`` names the road users of ``subject`` ("vehicles" and "all vehicles")."""
    found = re.search(rf"(?:{NOUN})\b", subject)
    if found is None:
        return False
    mine, theirs = [singular(w) for w in found.group(0).split()], [singular(w) for w in noun.split()]
    # "cones" are the "construction cones" taken; "vehicles" are not the "ego vehicle"
    return mine == theirs or (mine[-len(theirs) :] == theirs and mine[0] != "ego")
