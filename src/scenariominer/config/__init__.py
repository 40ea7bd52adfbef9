"""One typed configuration tree, loaded from TOML with environment overrides.

Every default is the value the papers use. Load with :func:`load_config`::

    cfg = load_config("scenariominer.toml")   # or load_config() for defaults + env
    cfg.preprocess.smooth_window_s

Environment variables ``SCENARIOMINER__<SECTION>__<FIELD>`` override file values, e.g.
``SCENARIOMINER__LLM__BACKEND=openai``. The file named by ``SCENARIOMINER_CONFIG`` is read when
no path is given.
"""

from __future__ import annotations

import dataclasses
import math
import os
import tomllib
import types
import typing
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar

from scenariominer import errors as _errors
from scenariominer.config.cbr import CbrConfig
from scenariominer.config.data import IngestConfig, PreprocessConfig, StoreConfig
from scenariominer.config.exec import ExecConfig
from scenariominer.config.explain import ExplainConfig
from scenariominer.config.llm import EmbeddingConfig, LLMConfig
from scenariominer.config.mining import MiningConfig
from scenariominer.config.represent import RepresentConfig
from scenariominer.config.tags import TagConfig

__all__ = [
    "CbrConfig",
    "Config",
    "ConfigError",
    "EmbeddingConfig",
    "ExecConfig",
    "ExplainConfig",
    "IngestConfig",
    "LLMConfig",
    "MiningConfig",
    "PreprocessConfig",
    "RepresentConfig",
    "StoreConfig",
    "TagConfig",
    "load_config",
]

ENV_PREFIX = "SCENARIOMINER__"


class ConfigError(_errors.ConfigError):
    """The configuration file or an override is invalid; the message names the key."""


@dataclass(frozen=True)
class Config:
    """Root of the configuration tree; one attribute per pipeline stage."""

    preprocess: PreprocessConfig = field(default_factory=PreprocessConfig)
    ingest: IngestConfig = field(default_factory=IngestConfig)
    store: StoreConfig = field(default_factory=StoreConfig)
    llm: LLMConfig = field(default_factory=LLMConfig)
    embedding: EmbeddingConfig = field(default_factory=EmbeddingConfig)
    tags: TagConfig = field(default_factory=TagConfig)
    explain: ExplainConfig = field(default_factory=ExplainConfig)
    mining: MiningConfig = field(default_factory=MiningConfig)
    represent: RepresentConfig = field(default_factory=RepresentConfig)
    cbr: CbrConfig = field(default_factory=CbrConfig)
    exec: ExecConfig = field(default_factory=ExecConfig)


T = TypeVar("T")


def _coerce(value: Any, tp: Any, key: str) -> Any:
    origin = typing.get_origin(tp)
    if dataclasses.is_dataclass(tp) and isinstance(tp, type):
        if not isinstance(value, dict):
            raise ConfigError(f"[{key}] must be a table")
        return _build(tp, value, key)
    if origin in (types.UnionType, typing.Union):
        args = [a for a in typing.get_args(tp) if a is not type(None)]
        if value is None:
            return None
        return _coerce(value, args[0], key)
    if origin is tuple:
        if not isinstance(value, list | tuple):
            raise ConfigError(f"{key} must be a list")
        (inner, *_rest) = typing.get_args(tp) or (Any,)
        return tuple(_coerce(v, inner, key) for v in value)
    if origin is dict:
        if not isinstance(value, dict):
            raise ConfigError(f"{key} must be a table")
        return dict(value)
    if tp is bool:
        if isinstance(value, str):
            if value.lower() in {"1", "true", "yes", "on"}:
                return True
            if value.lower() in {"0", "false", "no", "off"}:
                return False
        if not isinstance(value, bool):
            raise ConfigError(f"{key} must be true or false, got {value!r}")
        return value
    if tp is float:
        if isinstance(value, bool):
            raise ConfigError(f"{key} must be a number, got {value!r}")
        try:
            number = float(value)
        except (TypeError, ValueError):
            raise ConfigError(f"{key} must be a number, got {value!r}") from None
        if not math.isfinite(number):
            raise ConfigError(f"{key} must be a finite number, got {value!r}")
        return number
    if tp is int:
        if isinstance(value, bool):
            raise ConfigError(f"{key} must be an integer, got {value!r}")
        try:
            integer = int(value)
        except (TypeError, ValueError, OverflowError):  # OverflowError: int(inf)
            raise ConfigError(f"{key} must be an integer, got {value!r}") from None
        if isinstance(value, float) and integer != value:
            raise ConfigError(f"{key} must be an integer, got {value!r}")
        if not -(2**63) <= integer < 2**63:
            raise ConfigError(f"{key} must fit 64 bits, got {value!r}")
        return integer
    if tp is str:
        return str(value)
    return value


def _build(cls: type[T], data: dict[str, Any], prefix: str) -> T:
    hints = typing.get_type_hints(cls)
    names = {f.name for f in dataclasses.fields(cls)}  # type: ignore[arg-type]
    unknown = sorted(set(data) - names)
    if unknown:
        raise ConfigError(f"unknown key(s) {unknown} in [{prefix or 'root'}]; known: {sorted(names)}")
    kwargs = {k: _coerce(v, hints[k], f"{prefix}.{k}" if prefix else k) for k, v in data.items()}
    try:
        return cls(**kwargs)
    except ConfigError:
        raise
    except (ValueError, TypeError) as exc:  # a range check in the section's __post_init__
        raise ConfigError(f"[{prefix or 'root'}] {exc}") from None


def _env_overrides(environ: typing.Mapping[str, str]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, value in environ.items():
        if not key.startswith(ENV_PREFIX):
            continue
        parts = [p.lower() for p in key[len(ENV_PREFIX) :].split("__") if p]
        node = out
        for part in parts[:-1]:
            node = node.setdefault(part, {})
        if parts:
            node[parts[-1]] = value
    return out


def _merge(base: dict[str, Any], over: dict[str, Any]) -> dict[str, Any]:
    out = dict(base)
    for k, v in over.items():
        out[k] = _merge(out[k], v) if isinstance(v, dict) and isinstance(out.get(k), dict) else v
    return out


def load_config(path: str | Path | None = None, environ: typing.Mapping[str, str] | None = None) -> Config:
    """Load the configuration: defaults, then the TOML file, then environment overrides.

    Args:
        path: TOML file; ``None`` uses ``$SCENARIOMINER_CONFIG`` when set, else defaults only.
        environ: environment mapping (defaults to ``os.environ``).

    Raises:
        ConfigError: unreadable file, unknown section/key, or a value of the wrong type.
    """
    env = os.environ if environ is None else environ
    if path is None and env.get("SCENARIOMINER_CONFIG"):
        path = env["SCENARIOMINER_CONFIG"]
    data: dict[str, Any] = {}
    if path is not None:
        p = Path(path)
        try:
            data = tomllib.loads(p.read_text(encoding="utf-8"))
        except FileNotFoundError:
            raise ConfigError(f"config file {p} does not exist") from None
        except tomllib.TOMLDecodeError as exc:
            raise ConfigError(f"config file {p} is not valid TOML: {exc}") from None
    data = _merge(data, _env_overrides(env))
    try:
        return _build(Config, data, "")
    except ConfigError as exc:
        where = f"config file {path}" if path is not None else "configuration"
        raise ConfigError(f"{where} (or a {ENV_PREFIX}* variable): {exc}") from None
