"""A llama.cpp grammar (GBNF) of mining programs, built from the predicates' signatures.

Under this grammar the model can only write programs of the shape the sandbox runs:

* an optional ``description = '...'`` line and ``#`` comment lines;
* assignments ``name = expression``, where an expression is a defined-looking name or a call;
* calls to existing mining functions only, each with its arguments in signature order and of the
  right kind: an object set (a name or a nested call) where the signature has a ``Scenario``,
  the literal ``log_dir`` where it has the log, one of the allowed words for a text argument
  (:data:`scenariominer.mine.dsl._common.ARGUMENT_CHOICES`, Argoverse 2 categories and groups for
  ``category``), a number for a number, ``True``/``False`` for a flag; optional arguments by
  keyword, in signature order;
* ``scenario_and``/``scenario_or`` over a list of object sets, ``scenario_not(f)(...)`` and
  ``reverse_relationship(f)(...)`` with ``f``'s own arguments;
* a final ``output_scenario(name, description, log_dir, output_dir)``;
* optionally, the whole program in one ```` ```python ```` block, as the prompts ask.

What a context-free grammar cannot know (whether a name was defined before, whether a relation is
the one the description asks for) stays with the sandbox's static check and the repair loop.
The grammar is built from :data:`~scenariominer.mine.dsl.DSL_FUNCTIONS`, so a predicate added to
the DSL is offered to the model without touching this module.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from functools import cache
from typing import Any

__all__ = ["program_grammar"]

#: Allowed words of each text argument, by function and argument name.
Choices = Mapping[str, Mapping[str, tuple[str | None, ...]]]

_LETTERS = "abcdefghijklmnopqrstuvwxyz"
_WRAPPERS = ("scenario_not", "reverse_relationship")
_SET_OPS = ("scenario_and", "scenario_or")
_OUTPUT = "output_scenario"


def _rule(name: str) -> str:
    """GBNF rule names allow letters, digits and dashes only."""
    return name.replace("_", "-")


def _literal(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


@dataclass
class _Trie:
    children: dict[str, _Trie] = field(default_factory=dict)
    exact: bool = False  # a word ends here: the name may not stop here
    prefix: bool = False  # a forbidden prefix ends here: no name may reach this node


def _names_without(exact: Sequence[str], prefixes: Sequence[str], max_len: int = 40) -> str:
    """GBNF for identifiers other than the ``exact`` words and not starting with any of ``prefixes``.

    Built over the trie of the excluded words: at each node a name takes a character outside the
    trie (then anything), or follows the trie, or stops (unless a whole excluded word ends there).
    """
    root = _Trie()
    for words, attr in ((exact, "exact"), (prefixes, "prefix")):
        for word in words:
            node = root
            for ch in word:
                node = node.children.setdefault(ch, _Trie())
            setattr(node, attr, True)

    def expr(node: _Trie, depth: int) -> str:
        pool = _LETTERS if depth == 0 else _LETTERS + "0123456789_"
        free = "".join(c for c in pool if c not in node.children)
        alternatives = [f"[{free}] [a-z0-9_]{{0,{max_len - depth - 1}}}"] if free else []
        for ch, child in sorted(node.children.items()):
            if not child.prefix:
                alternatives.append(f'"{ch}" {expr(child, depth + 1)}')
        body = "(" + " | ".join(alternatives) + ")"
        return body + "?" if depth > 0 and not node.exact else body

    return expr(root, 0)


def _kind(param: inspect.Parameter) -> str:
    text = str(param.annotation)
    if "Scenario" in text and "Callable" not in text and "Sequence" not in text:
        return "objects"
    if "LogContext" in text:
        return "log_dir"
    if text == "bool":
        return "flag"
    if text in ("int", "float", "int | None", "float | None", "int | float"):
        return "number"
    if text in ("str", "str | None"):
        return "text"
    return "other"


def _text_values(func: str, param: str, choices: Choices) -> str:
    if param == "category":
        return "category"
    allowed = [v for v in choices.get(func, {}).get(param, ()) if v is not None]
    if not allowed:
        return "text"
    return "(" + " | ".join(_literal(repr(v)) for v in allowed) + ")"


def _value(kind: str, func: str, param: str, choices: Choices) -> str:
    return {
        "objects": "expr",
        "log_dir": '"log_dir"',
        "flag": '("True" | "False")',
        "number": "number",
    }.get(kind) or _text_values(func, param, choices)


def _arguments(func: str, params: list[inspect.Parameter], choices: Choices) -> tuple[str, str | None] | None:
    """``func``'s required arguments (in order) and the alternatives of its optional keyword ones.

    Required object sets and ``log_dir`` are positional; a required text, number or flag may be
    written with or without its keyword. Optional arguments come by keyword, in any order.
    ``None`` when a parameter is of a kind the grammar does not know (the function is left out).
    """
    required: list[str] = []
    optional: list[str] = []
    for p in params:
        kind = _kind(p)
        if kind == "other":
            return None
        value = _value(kind, func, p.name, choices)
        if p.default is not p.empty:
            optional.append(f'"{p.name}=" {value}')
        elif kind in ("text", "number", "flag"):
            required.append(f'"{p.name}="? {value}')
        else:
            required.append(value)
    return ' ", " '.join(required), (" | ".join(optional) or None)


@cache
def program_grammar(functions: tuple[tuple[str, Callable[..., Any]], ...] | None = None) -> str:
    """The GBNF grammar of a mining program over ``functions`` (default: the whole DSL).

    Args:
        functions: ``(name, function)`` pairs; ``None`` means every function of
            :data:`~scenariominer.mine.dsl.DSL_FUNCTIONS`.

    Returns:
        The grammar text (root rule ``root``), accepted by ``llama_cpp.LlamaGrammar.from_string``.
    """
    from scenariominer.data.categories import AV2_CATEGORIES, CATEGORY_GROUPS
    from scenariominer.mine.dsl import DSL_FUNCTIONS
    from scenariominer.mine.dsl._common import ARGUMENT_CHOICES

    table = dict(functions) if functions is not None else dict(DSL_FUNCTIONS)
    rules: dict[str, str] = {}
    calls: list[str] = []
    for name, func in table.items():
        if name in (*_WRAPPERS, *_SET_OPS, _OUTPUT):
            continue
        params = list(inspect.signature(func).parameters.values())
        spec = _arguments(name, params, ARGUMENT_CHOICES)
        if spec is None:
            continue
        required, optional = spec
        rule = _rule(name)
        if optional is None:
            rules[f"args-{rule}"] = required
        else:
            rules[f"opt-{rule}"] = optional
            rules[f"args-{rule}"] = f'{required} (", " opt-{rule}){{0,6}}'
        rules[f"call-{rule}"] = f'"{name}(" args-{rule} ")"'
        calls.append(f"call-{rule}")
        kinds = [_kind(p) for p in params]
        if "scenario_not" in table and kinds[:1] == ["objects"]:
            rules[f"not-{rule}"] = f'"scenario_not({name})(" args-{rule} ")"'
            calls.append(f"not-{rule}")
        if "reverse_relationship" in table and kinds[:2] == ["objects", "objects"]:
            rules[f"rev-{rule}"] = f'"reverse_relationship({name})(" args-{rule} ")"'
            calls.append(f"rev-{rule}")
    for op in _SET_OPS:
        if op in table:
            rules[f"call-{_rule(op)}"] = f'"{op}([" expr (", " expr)+ "])"'
            calls.append(f"call-{_rule(op)}")
    categories = sorted({*AV2_CATEGORIES, *CATEGORY_GROUPS})
    head = {
        # The prompts ask for one ```python block; the fence may be written or left out.
        "root": "fence-open? description? line{0,16} output fence-close?",
        "fence-open": '"```python\\n"',
        "fence-close": '"```"',
        "description": '"description = \'" [^\'\\n\\\\]{0,200} "\'\\n"',
        "line": '(comment | assign) "\\n"',
        "comment": '"#" [^\\n]{0,160}',
        "assign": 'name " = " expr',
        "output": f'"{_OUTPUT}(" expr (", description" (", log_dir" (", output_dir")?)?)? ")" "\\n"?',
        # any lower-case identifier but log_dir (the log is never an object set or a new name) and
        # none named like the output call (a model about to write it must not drift into a name)
        "name": _names_without(("log_dir",), (_OUTPUT,)),
        "expr": "name | call",
        "call": " | ".join(calls),
        "number": '"-"? ([0-9]{1,4} ("." [0-9]{1,3})? | "inf" | "np.inf")',
        "text": '"\'" [a-zA-Z_ ]{1,30} "\'"',
        "category": '"\'" (' + " | ".join(_literal(c) for c in categories) + ') "\'"',
    }
    return "\n".join(f"{k} ::= {v}" for k, v in {**head, **rules}.items()) + "\n"
