"""Commit messages of a scenario library: the scenario a commit adds or changes.

A team that keeps its scenario definitions in version control names each one in a commit
message: "feat(scenarios): add moving buses on an intersection", "fix: ped near ego scenario now
requires < 5 m to ego", "fix: stopped truck scenario now counts parked trucks too".
:func:`commit_message` drops the conventional-commit type and scope and the verb that adds the
scenario, and states a fixed scenario as what it now asks for ("ped near ego within 5 m of ego",
"stopped trucks or parked trucks"). Text that is not a commit message is returned as it is.
"""

from __future__ import annotations

import re

__all__ = ["commit_message"]

#: "feat(scenarios)!: ", "fix: ", "chore(library): ": the type and scope of a conventional commit.
_TYPE = re.compile(
    r"^(?:feat|feature|fix|bugfix|hotfix|chore|refactor|docs|test|tests|perf|style|build|ci|revert)"
    r"(?:\s*\([^)]*\))?!?:\s*",
    re.IGNORECASE,
)
#: "add (a new) scenario for", "introduce", "support": the verb that adds what follows.
_ADDED = re.compile(
    r"^(?:add|adds|added|introduce[sd]?|create[sd]?|implement(?:s|ed)?|support(?:s|ed)?|define[sd]?"
    r"|include[sd]?|cover(?:s|ed)?|new)"
    r"(?: (?:a |an |the )?(?:new )?(?:scenarios?|cases?|tests?|quer(?:y|ies)|filters?|definitions?)"
    r"(?: (?:for|of|with|where|covering|on|about))?)?\s+",
    re.IGNORECASE,
)
#: "X scenario now requires Y": the scenario as it now is.
_NOW = re.compile(
    r"^(?P<name>.+?) scenarios? (?:now |also |then )?(?:requires?|needs?|checks?|uses?|matches|means)\s+"
    r"(?P<rule>.+)$",
    re.IGNORECASE,
)
#: "X scenario now counts Y too": Y is found as well.
_TOO = re.compile(
    r"^(?P<name>.+?) scenarios? (?:now |also )?(?:counts?|includes?|covers?|matches|finds?)\s+"
    r"(?P<more>.+?)(?: too| as well| also)?$",
    re.IGNORECASE,
)


def commit_message(text: str) -> str:
    """``text`` as the scenario it names, when it is a commit message of a scenario library.

    "feat(scenarios): add moving buses on an intersection" -> "find moving buses on an
    intersection"; "fix: ped near ego scenario now requires < 5 m to ego" -> "ped near ego < 5 m
    of ego"; "fix: stopped truck scenario now counts parked trucks too" -> "stopped trucks or
    parked trucks".
    """
    stripped = _TYPE.sub("", text.strip(), count=1)
    if stripped == text.strip():
        return text
    added = _ADDED.sub("find ", stripped, count=1)
    if added != stripped:
        return added
    if match := _NOW.match(stripped):
        rule = re.sub(r"\b(\d+(?:\.\d+)? ?m) (?:to|from)\b", r"\1 of", match["rule"])
        return f"{match['name']} {rule}"
    if match := _TOO.match(stripped):
        name, more = match["name"].split(), match["more"].split()
        # "stopped bus" (a scenario's name is singular): plural like what it now counts
        if more and more[-1] != name[-1] and more[-1].startswith(name[-1]):
            name[-1] = more[-1]
        return f"{' '.join(name)} or {match['more']}"
    return stripped
