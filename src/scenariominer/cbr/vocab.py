"""Risk types and evasive manoeuvres: the two configurable vocabularies of the case base.

Defaults are the paper's Table 1, shipped as ``risk_types.toml`` and ``manoeuvres.toml`` beside
this module; ``cbr.risk_types_file`` / ``cbr.manoeuvres_file`` name replacements in the same
format (one TOML table per entry, keyed by its identifier).
"""

from __future__ import annotations

import re
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from scenariominer import errors as _errors

__all__ = [
    "CbrError",
    "Manoeuvre",
    "ManoeuvreSet",
    "RiskType",
    "RiskTypeSet",
    "load_manoeuvres",
    "load_risk_types",
]

_HERE = Path(__file__).parent
_NAME_RE = re.compile(r"^[a-z][a-z0-9_]{0,63}$")


class CbrError(_errors.ScenarioMinerError, ValueError):
    """Case-based reasoning cannot go on: a bad vocabulary file, case, import row or query."""


@dataclass(frozen=True)
class RiskType:
    """One risk type (key part of a case).

    Attributes:
        name: identifier (lower-case ``[a-z0-9_]``).
        label: the paper's wording, shown to the model.
        definition: what it means, given to the model in the system prompt.
    """

    name: str
    label: str
    definition: str


@dataclass(frozen=True)
class Manoeuvre:
    """One evasive manoeuvre and how the rollout check executes it.

    Attributes:
        name: identifier; the model answers with it (JSON-schema enum).
        label: the paper's wording.
        effort: rank used to label synthetic cases (least effort that avoids the conflict wins).
        accel_mps2: longitudinal acceleration held once reached (negative = braking), m/s².
        jerk_mps3: build-up rate of that acceleration, m/s³.
        lateral_m: sideways displacement, left positive, metres.
        lateral_s: seconds the displacement takes.
    """

    name: str
    label: str
    effort: float
    accel_mps2: float
    jerk_mps3: float
    lateral_m: float
    lateral_s: float


@dataclass(frozen=True)
class RiskTypeSet:
    """The configured risk types, in file order, and where they came from."""

    types: tuple[RiskType, ...]
    source: str

    @property
    def names(self) -> tuple[str, ...]:
        """Identifiers in file order."""
        return tuple(t.name for t in self.types)

    def get(self, name: str) -> RiskType:
        """The risk type called ``name``.

        Raises:
            CbrError: no such risk type (the message lists the known ones).
        """
        for t in self.types:
            if t.name == name:
                return t
        raise CbrError(f"unknown risk type {name!r}; known: {', '.join(self.names)}")


@dataclass(frozen=True)
class ManoeuvreSet:
    """The configured manoeuvres, in file order, and where they came from."""

    manoeuvres: tuple[Manoeuvre, ...]
    source: str

    @property
    def names(self) -> tuple[str, ...]:
        """Identifiers in file order (the JSON-schema enum)."""
        return tuple(m.name for m in self.manoeuvres)

    def get(self, name: str) -> Manoeuvre:
        """The manoeuvre called ``name``.

        Raises:
            CbrError: no such manoeuvre.
        """
        for m in self.manoeuvres:
            if m.name == name:
                return m
        raise CbrError(f"unknown manoeuvre {name!r}; known: {', '.join(self.names)}")

    def by_effort(self) -> tuple[Manoeuvre, ...]:
        """Manoeuvres from least to most effort (file order breaks ties)."""
        order = {m.name: i for i, m in enumerate(self.manoeuvres)}
        return tuple(sorted(self.manoeuvres, key=lambda m: (m.effort, order[m.name])))


def _read(path: Path) -> dict[str, Any]:
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise CbrError(f"{path}: file does not exist") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise CbrError(f"{path}: not valid TOML: {exc}") from None
    if not data:
        raise CbrError(f"{path}: defines no entries")
    for name, entry in data.items():
        if not _NAME_RE.match(name):
            raise CbrError(f"{path}: {name!r} is not a valid identifier (lower-case letters, digits, _)")
        if not isinstance(entry, dict):
            raise CbrError(f"{path}: {name} must be a table")
    return data


def _text(path: Path, name: str, entry: dict[str, Any], key: str) -> str:
    value = entry.get(key)
    if not isinstance(value, str) or not value.strip():
        raise CbrError(f"{path}: {name}.{key} must be a non-empty string")
    return value.strip()


def _number(path: Path, name: str, entry: dict[str, Any], key: str) -> float:
    value = entry.get(key)
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise CbrError(f"{path}: {name}.{key} must be a number, got {value!r}")
    return float(value)


def load_risk_types(path: str | Path | None = None) -> RiskTypeSet:
    """Read the risk types (``None`` or ``""``: the paper's seven).

    Raises:
        CbrError: unreadable file, bad identifier, or an entry without label/definition.
    """
    p = Path(path) if path else _HERE / "risk_types.toml"
    data = _read(p)
    types = tuple(
        RiskType(name, _text(p, name, e, "label"), _text(p, name, e, "definition"))
        for name, e in data.items()
    )
    return RiskTypeSet(types, str(path) if path else "builtin")


def load_manoeuvres(path: str | Path | None = None) -> ManoeuvreSet:
    """Read the manoeuvres (``None`` or ``""``: the paper's eight).

    Raises:
        CbrError: unreadable file, bad identifier, missing or non-numeric kinematics.
    """
    p = Path(path) if path else _HERE / "manoeuvres.toml"
    data = _read(p)
    out = []
    for name, e in data.items():
        m = Manoeuvre(
            name,
            _text(p, name, e, "label"),
            _number(p, name, e, "effort"),
            _number(p, name, e, "accel_mps2"),
            _number(p, name, e, "jerk_mps3"),
            _number(p, name, e, "lateral_m"),
            _number(p, name, e, "lateral_s"),
        )
        if m.jerk_mps3 <= 0 or m.lateral_s <= 0:
            raise CbrError(f"{p}: {name}: jerk_mps3 and lateral_s must be positive")
        out.append(m)
    return ManoeuvreSet(tuple(out), str(path) if path else "builtin")
