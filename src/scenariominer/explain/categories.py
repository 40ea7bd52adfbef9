"""Scenario categories the LLM chooses from (braking paper, section III-D.2, Fig. 4d, Table III).

The default set is the paper's four in-distribution categories plus the two fallbacks
``unknown_but_relevant`` and ``not_relevant``. Users may supply their own categories in a TOML
file mapping each name to its definition::

    cut_in = "Another vehicle moves into the ego's lane just ahead of it ..."
    lead_brake = "The vehicle directly ahead of the ego brakes suddenly ..."

(or the same under a ``[categories]`` table). The two fallbacks are added with their default
definitions when a file does not define them, so the LLM always has a way to say "none of these".
"""

from __future__ import annotations

import hashlib
import json
import re
import tomllib
from dataclasses import dataclass
from pathlib import Path

from scenariominer import errors as _errors

__all__ = [
    "DEFAULT_CATEGORIES",
    "ERROR_CATEGORY",
    "FALLBACK_CATEGORIES",
    "INVALID_CATEGORY",
    "NOT_RELEVANT",
    "PENDING_CATEGORY",
    "RESERVED_NAMES",
    "UNKNOWN_BUT_RELEVANT",
    "CategoryDef",
    "CategoryFileError",
    "CategorySet",
    "load_categories",
]

#: Fallback: the guest causes the braking, but no listed category fits.
UNKNOWN_BUT_RELEVANT = "unknown_but_relevant"
#: Fallback: the guest is not why the ego brakes.
NOT_RELEVANT = "not_relevant"
#: Recorded when the LLM's answer stays invalid (bad JSON, unknown category) after the repair round.
INVALID_CATEGORY = "invalid"
#: Recorded when the LLM backend itself failed (server down, context overflow).
ERROR_CATEGORY = "error"
#: Recorded for an event the LLM has not classified yet (``--limit`` reached).
PENDING_CATEGORY = "pending"
#: Names a category file may not use: they mark outcomes, not scenarios.
RESERVED_NAMES = frozenset({INVALID_CATEGORY, ERROR_CATEGORY, PENDING_CATEGORY})

_NAME_RE = re.compile(r"^[a-z][a-z0-9_]{0,63}$")


class CategoryFileError(_errors.ExplainError, ValueError):
    """A category file cannot be used; the message names the file and the problem."""

    def __init__(self, path: str | Path, problem: str) -> None:
        self.path = str(path)
        self.problem = problem
        super().__init__(f"{self.path}: {problem}")


@dataclass(frozen=True)
class CategoryDef:
    """One scenario category.

    Attributes:
        name: identifier the LLM answers with (lower-case, ``[a-z0-9_]``).
        definition: what the category means, in the words given to the LLM.
    """

    name: str
    definition: str


#: The braking paper's categories, each defined in terms the tag description uses.
DEFAULT_CATEGORIES: tuple[CategoryDef, ...] = (
    CategoryDef(
        "cut_in",
        "Another vehicle (or cyclist) that was beside the ego or ahead of it in a neighbouring lane "
        "moves sideways into the ego's lane and ends up directly in front of the ego, travelling in the "
        "same direction; the ego brakes to keep its distance. Typical tags: relative heading SAME, the "
        "guest VEERING or TURNING while ahead, relative position changing to FRONT.",
    ),
    CategoryDef(
        "left_oppo",
        "The ego turns left, or waits to turn left, while an oncoming object travelling in the "
        "opposite direction approaches or passes in front of it; the ego brakes or waits to yield. "
        "Typical tags: ego lateral TURNING_LEFT or VEERING_LEFT, relative heading OPPOSITE.",
    ),
    CategoryDef(
        "right_ped",
        "The ego turns right, or is about to, while a pedestrian crosses the road the ego is turning "
        "into; the ego brakes or waits for the pedestrian. Typical tags: ego lateral TURNING_RIGHT or "
        "VEERING_RIGHT, the guest is a PEDESTRIAN.",
    ),
    CategoryDef(
        "obj_crossing",
        "The ego drives (mostly) straight while a vehicle, cyclist or motorcyclist (not a pedestrian) "
        "crosses its path in front of it, moving from left to right or right to left across the ego's "
        "direction of travel; the ego brakes to let it pass. Typical tags: relative heading LEFT or "
        "RIGHT while the guest is ahead.",
    ),
)

#: Definitions of the two fallback categories.
FALLBACK_CATEGORIES: tuple[CategoryDef, ...] = (
    CategoryDef(
        UNKNOWN_BUT_RELEVANT,
        "The guest clearly makes the ego brake, but none of the other categories describes how.",
    ),
    CategoryDef(
        NOT_RELEVANT,
        "The guest is not the reason for the ego's braking: it stays away from the ego's path, "
        "moves away, or the risk tags are only a brief coincidence.",
    ),
)


@dataclass(frozen=True)
class CategorySet:
    """The categories given to the LLM, in prompt order (fallbacks last).

    Attributes:
        categories: the definitions; names are unique.
        source: ``"builtin"`` or the path of the file they were read from.
    """

    categories: tuple[CategoryDef, ...]
    source: str = "builtin"

    def __post_init__(self) -> None:
        names = [c.name for c in self.categories]
        if len(set(names)) != len(names):
            raise ValueError(f"category names repeat: {names}")
        if not names:
            raise ValueError("a category set needs at least one category")

    @classmethod
    def default(cls) -> CategorySet:
        """The braking paper's categories."""
        return cls(DEFAULT_CATEGORIES + FALLBACK_CATEGORIES)

    @property
    def names(self) -> tuple[str, ...]:
        """Every category name, in prompt order."""
        return tuple(c.name for c in self.categories)

    @property
    def scenario_names(self) -> tuple[str, ...]:
        """The names of the specific scenario categories (the fallbacks excluded)."""
        fallbacks = {c.name for c in FALLBACK_CATEGORIES}
        return tuple(n for n in self.names if n not in fallbacks)

    def definition(self, name: str) -> str:
        """Definition of ``name``; ``KeyError`` listing the known names when absent."""
        for c in self.categories:
            if c.name == name:
                return c.definition
        raise KeyError(f"unknown category {name!r}; known: {list(self.names)}")

    @property
    def fingerprint(self) -> str:
        """Short hash of the names and definitions (part of the analysis fingerprint)."""
        blob = json.dumps([[c.name, c.definition] for c in self.categories], ensure_ascii=False)
        return hashlib.sha256(blob.encode("utf-8")).hexdigest()[:16]


def load_categories(path: str | Path | None = None) -> CategorySet:
    """Load the categories from a TOML file, or the paper's defaults when ``path`` is empty.

    Args:
        path: TOML file with ``name = "definition"`` entries (top level or under ``[categories]``).

    Raises:
        CategoryFileError: the file is missing or not TOML, a value is not a non-empty string, a
            name is not lower-case ``[a-z0-9_]`` or is reserved (``invalid``, ``error``, ``pending``),
            or no specific category is defined.
    """
    if path is None or str(path) == "":
        return CategorySet.default()
    p = Path(path)
    try:
        data = tomllib.loads(p.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise CategoryFileError(p, "category file does not exist") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise CategoryFileError(p, f"cannot read the category file ({exc})") from None
    except tomllib.TOMLDecodeError as exc:
        raise CategoryFileError(p, f"not valid TOML ({exc})") from None
    if set(data) == {"categories"} and isinstance(data["categories"], dict):
        data = data["categories"]
    defs: list[CategoryDef] = []
    for name, definition in data.items():
        if not _NAME_RE.match(name):
            raise CategoryFileError(p, f"category name {name!r} must be lower-case letters, digits and _")
        if name in RESERVED_NAMES:
            raise CategoryFileError(p, f"category name {name!r} is reserved (it marks an outcome)")
        if not isinstance(definition, str) or not definition.strip():
            raise CategoryFileError(p, f"category {name!r} needs a non-empty definition string")
        defs.append(CategoryDef(name, " ".join(definition.split())))
    given = {d.name for d in defs}
    specific = [d for d in defs if d.name not in {c.name for c in FALLBACK_CATEGORIES}]
    if not specific:
        raise CategoryFileError(p, "the file defines no scenario category besides the fallbacks")
    fallbacks = [d for d in defs if d.name in {c.name for c in FALLBACK_CATEGORIES}]
    fallbacks += [c for c in FALLBACK_CATEGORIES if c.name not in given]
    order = {c.name: i for i, c in enumerate(FALLBACK_CATEGORIES)}
    fallbacks.sort(key=lambda c: order[c.name])
    return CategorySet(tuple(specific + fallbacks), source=str(p))
