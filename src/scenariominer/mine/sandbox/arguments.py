"""Signature-aware check of the arguments of every mining-function call, before anything runs.

A model that writes ``in_same_lane(vehicles, log_dir)`` gets, from Python, "missing 1 required
positional argument: 'log_dir'", and typically answers by dropping more arguments. This check
reads each call against the function's signature and names the argument at fault instead:

    argument 2 (related_candidates) of in_same_lane must be an object set (a variable holding
    the result of a mining function); you passed log_dir

Kinds come from the annotations of the DSL functions: ``Scenario`` is an object set,
``LogContext`` is ``log_dir``, ``str``/``int``/``float`` are literals or variables. Only what is
certain from the program text is reported: a variable may hold anything, so only the special name
``log_dir`` and literals are judged by kind; the direction argument is checked against its values.
``scenario_not(f)(...)`` and ``reverse_relationship(f)(...)`` are checked against ``f``.
"""

from __future__ import annotations

import ast
import inspect
from collections.abc import Callable, Mapping
from functools import cache
from typing import Any

from scenariominer.mine.dsl._common import _DIRECTION_ALIASES, _DIRECTIONS

__all__ = ["DIRECTIONS", "ArgumentFault", "check_call_arguments"]

#: Values the ``direction`` argument of the relative-direction predicates accepts.
DIRECTIONS = frozenset(_DIRECTIONS) | frozenset(_DIRECTION_ALIASES)

#: The node at fault and the message naming the problem.
ArgumentFault = tuple[ast.AST, str]
_WRAPPERS = frozenset({"scenario_not", "reverse_relationship"})
#: Functions whose ``direction`` is a side of an object (others use their own words, e.g. 'same').
_SIDE_DIRECTION = frozenset(
    {"has_objects_in_relative_direction", "get_objects_in_relative_direction", "being_crossed_by"}
)
_OBJECT_SET_HINT = "an object set (a variable holding the result of a mining function)"


def _kind(annotation: Any) -> str:
    text = str(annotation)
    if "Scenario" in text and "Callable" not in text:
        return "objects"
    if "LogContext" in text:
        return "log_dir"
    if text in ("str", "<class 'str'>"):
        return "text"
    if text in ("int", "float", "<class 'int'>", "<class 'float'>", "int | float", "float | int"):
        return "number"
    return "any"


@cache
def _signature(func: Callable[..., Any]) -> inspect.Signature:
    return inspect.signature(func)


def _fault(node: ast.AST, message: str) -> ArgumentFault:
    return node, message


def _describe(arg: ast.expr) -> str:
    if isinstance(arg, ast.Name):
        return arg.id
    if isinstance(arg, ast.Constant):
        return repr(arg.value)
    return ast.unparse(arg)[:60]


def _mismatch(kind: str, arg: ast.expr) -> str | None:
    """What is wrong with ``arg`` for a parameter of ``kind`` (``None``: fine or not knowable)."""
    is_log_dir = isinstance(arg, ast.Name) and arg.id == "log_dir"
    literal = arg.value if isinstance(arg, ast.Constant) else None
    if kind == "objects" and (is_log_dir or isinstance(arg, ast.Constant)):
        return f"must be {_OBJECT_SET_HINT}"
    if kind == "log_dir" and not is_log_dir:
        return "must be log_dir (the log the program runs on)"
    if kind == "text" and (is_log_dir or (literal is not None and not isinstance(literal, str))):
        return "must be a text, e.g. 'left'"
    if kind == "number" and (
        is_log_dir or isinstance(literal, str) or (isinstance(arg, ast.Constant) and literal is None)
    ):
        return "must be a number"
    return None


def _callee(call: ast.Call) -> str | None:
    """Name of the mining function ``call`` calls (``f`` also for ``scenario_not(f)(...)``)."""
    target = call.func
    if isinstance(target, ast.Call) and isinstance(target.func, ast.Name) and target.func.id in _WRAPPERS:
        inner = target.args[0] if len(target.args) == 1 else None
        return inner.id if isinstance(inner, ast.Name) else None
    return target.id if isinstance(target, ast.Name) else None


def _keyword_fault(
    name: str, kw: ast.keyword, params: list[inspect.Parameter], bound: dict[str, ast.expr]
) -> ArgumentFault | None:
    by_name = {p.name: p for p in params}
    named = by_name.get(str(kw.arg))
    if named is None:
        if any(p.kind is p.VAR_KEYWORD for p in params):
            return None
        names = ", ".join(p.name for p in params if p.kind is not p.VAR_KEYWORD)
        return _fault(kw.value, f"{name} has no argument named {kw.arg!r}; its arguments are {names}")
    if named.name in bound:
        return _fault(kw.value, f"argument {kw.arg!r} of {name} is given twice (by position and by name)")
    problem = _mismatch(_kind(named.annotation), kw.value)
    if problem is not None:
        return _fault(kw.value, f"argument {kw.arg!r} of {name} {problem}; you passed {_describe(kw.value)}")
    return None


def _direction_fault(name: str, direction: ast.expr | None) -> ArgumentFault | None:
    if name not in _SIDE_DIRECTION or not isinstance(direction, ast.Constant):
        return None
    value = direction.value
    if isinstance(value, str) and value.lower() not in DIRECTIONS:
        return _fault(
            direction,
            f"direction of {name} must be one of 'left', 'right', 'forward', 'backward'; "
            f"you passed {value!r}",
        )
    return None


def check_call_arguments(call: ast.Call, functions: Mapping[str, Callable[..., Any]]) -> ArgumentFault | None:
    """The first argument of ``call`` that cannot fit the mining function's signature, if any.

    Args:
        call: a call node of the program.
        functions: the mining functions by name.

    Returns:
        ``None`` when the call is not a mining-function call or its arguments may fit.
    """
    name = _callee(call)
    if name is None or name not in functions or name in _WRAPPERS:
        return None
    if any(isinstance(a, ast.Starred) for a in call.args) or any(k.arg is None for k in call.keywords):
        return None  # *args / **kwargs: not knowable statically
    params = list(_signature(functions[name]).parameters.values())
    positional = [p for p in params if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
    if len(call.args) > len(positional) and not any(p.kind is p.VAR_POSITIONAL for p in params):
        return _fault(
            call,
            f"{name} takes at most {len(positional)} positional argument(s) "
            f"({', '.join(p.name for p in positional)}); you passed {len(call.args)}",
        )
    bound: dict[str, ast.expr] = {}
    for i, (param, arg) in enumerate(zip(positional, call.args, strict=False), start=1):
        problem = _mismatch(_kind(param.annotation), arg)
        if problem is not None:
            return _fault(
                arg, f"argument {i} ({param.name}) of {name} {problem}; you passed {_describe(arg)}"
            )
        bound[param.name] = arg
    for kw in call.keywords:
        fault = _keyword_fault(name, kw, params, bound)
        if fault is not None:
            return fault
        bound[str(kw.arg)] = kw.value
    missing = [p.name for p in positional if p.default is p.empty and p.name not in bound]
    if missing:
        usage = f"{name}({', '.join(p.name for p in positional)})"
        return _fault(call, f"{name} needs {', '.join(missing)}: call it as {usage}")
    return _direction_fault(name, bound.get("direction"))
