"""The sandbox's first line of defence: a static whitelist check of a program, and the error vocabulary."""

from __future__ import annotations

import ast
from collections.abc import Collection
from dataclasses import dataclass
from enum import StrEnum

from scenariominer.config.mining import SandboxConfig
from scenariominer.mine.dsl import DSL_FUNCTIONS
from scenariominer.mine.sandbox.arguments import check_call_arguments
from scenariominer.mine.scenario import Scenario

PROGRAM_FILENAME = "<program>"

#: Builtins available to programs (``range`` is capped, ``print`` discards its output).
SAFE_BUILTIN_NAMES: frozenset[str] = frozenset(
    {
        "len",
        "min",
        "max",
        "range",
        "abs",
        "sorted",
        "list",
        "dict",
        "set",
        "tuple",
        "enumerate",
        "zip",
        "bool",
        "int",
        "float",
        "str",
        "sum",
        "any",
        "all",
        "round",
        "print",
        "True",
        "False",
        "None",
    }
)

#: Variables every program starts with.
PREDEFINED_NAMES: frozenset[str] = frozenset(
    {"log_dir", "log", "description", "output_dir", "inf", "np", "math"}
)

#: The one predefined name a program may assign, and only in its first statement, to a plain
#: string literal: every RefAV program begins with ``description = '...'`` (RefAV ``exec``s the
#: program, so that value is the description it passes to ``output_scenario``).
DECLARABLE_NAME = "description"

#: Attribute names a program may read on any object (container methods).
ALLOWED_ATTRIBUTES: frozenset[str] = frozenset({"append", "extend", "items", "keys", "values", "get"})

#: ``name.attribute`` pairs allowed in addition (numeric constants).
ALLOWED_QUALIFIED: frozenset[tuple[str, str]] = frozenset(
    {("np", "inf"), ("np", "pi"), ("math", "inf"), ("math", "pi")}
)

_ALLOWED_NODES: tuple[type[ast.AST], ...] = (
    ast.Module,
    ast.Expr,
    ast.Assign,
    ast.AugAssign,
    ast.AnnAssign,
    ast.For,
    ast.If,
    ast.Pass,
    ast.Break,
    ast.Continue,
    ast.Assert,
    ast.Call,
    ast.keyword,
    ast.Name,
    ast.Constant,
    ast.Attribute,
    ast.Subscript,
    ast.Slice,
    ast.List,
    ast.Tuple,
    ast.Dict,
    ast.Set,
    ast.Starred,
    ast.ListComp,
    ast.SetComp,
    ast.DictComp,
    ast.comprehension,
    ast.BinOp,
    ast.UnaryOp,
    ast.BoolOp,
    ast.Compare,
    ast.IfExp,
    ast.JoinedStr,
    ast.FormattedValue,
    ast.Load,
    ast.Store,
    ast.operator,
    ast.unaryop,
    ast.boolop,
    ast.cmpop,
    ast.expr_context,
)

_FORBIDDEN_REASONS: dict[type[ast.AST], str] = {
    ast.Import: "imports are not allowed; every mining function is already available",
    ast.ImportFrom: "imports are not allowed; every mining function is already available",
    ast.FunctionDef: "defining functions is not allowed; write the program as a sequence of calls",
    ast.AsyncFunctionDef: "defining functions is not allowed; write the program as a sequence of calls",
    ast.Lambda: "lambda is not allowed; write the program as a sequence of calls",
    ast.ClassDef: "defining classes is not allowed",
    ast.While: "while loops are not allowed; predicates already cover all timestamps (or use a for loop)",
    ast.Try: "try/except is not allowed; the miner reports errors itself",
    ast.Raise: "raise is not allowed",
    ast.With: "with statements are not allowed",
    ast.AsyncWith: "with statements are not allowed",
    ast.AsyncFor: "async code is not allowed",
    ast.Global: "global is not allowed",
    ast.Nonlocal: "nonlocal is not allowed",
    ast.Delete: "del is not allowed",
    ast.Yield: "yield is not allowed",
    ast.YieldFrom: "yield is not allowed",
    ast.Await: "await is not allowed",
    ast.GeneratorExp: "generator expressions are not allowed; use a list comprehension [...]",
    ast.NamedExpr: "the := operator is not allowed",
    ast.Match: "match statements are not allowed",
}

_DENIED_CALL_HINTS: dict[str, str] = {
    name: "it is not available to mining programs"
    for name in (
        "open",
        "eval",
        "exec",
        "compile",
        "getattr",
        "setattr",
        "delattr",
        "hasattr",
        "globals",
        "locals",
        "vars",
        "dir",
        "input",
        "breakpoint",
        "type",
        "object",
        "memoryview",
        "help",
        "exit",
        "quit",
        "id",
        "format",
        "iter",
        "next",
        "super",
        "classmethod",
        "staticmethod",
        "property",
    )
}


class ErrorKind(StrEnum):
    """Why a program produced no scenario."""

    SYNTAX = "syntax"
    """The text is not valid Python."""
    FORBIDDEN = "forbidden"
    """The program uses a construct or name outside the whitelist (refused before running)."""
    RUNTIME = "runtime"
    """The program raised an exception while running (wrong arguments, missing map, ...)."""
    TIMEOUT = "timeout"
    """The program ran longer than the wall-clock or CPU limit and was killed."""
    MEMORY = "memory"
    """The program tried to allocate more memory than allowed."""
    INVALID_OUTPUT = "invalid_output"
    """The program finished without calling ``output_scenario`` exactly once with a scenario."""
    PLAN = "plan"
    """The description's plan names something the plan-to-program rules cannot express."""


@dataclass(frozen=True)
class ProgramError:
    """A structured failure of a mining program.

    Attributes:
        kind: category of the failure.
        message: one or two sentences naming the cause, with the line when known.
        line: 1-based program line the failure is attributed to, if known.
    """

    kind: ErrorKind
    message: str
    line: int | None = None

    def feedback(self) -> str:
        """The error as text to show a language model that should repair the program."""
        return f"{self.kind.value} error: {self.message}"

    def __str__(self) -> str:
        return self.feedback()


@dataclass(frozen=True)
class ProgramResult:
    """Outcome of running one program on one log.

    Attributes:
        scenario: the (post-processed) scenario the program output, or ``None`` on failure.
        error: the failure, or ``None`` on success.
        elapsed_s: wall-clock seconds spent, checks and process start-up included.
        description: the description the program passed to ``output_scenario``, if any.
    """

    scenario: Scenario | None
    error: ProgramError | None
    elapsed_s: float
    description: str | None = None

    @property
    def ok(self) -> bool:
        """Whether the program produced a scenario."""
        return self.error is None and self.scenario is not None


# ---------------------------------------------------------------------- static checks


def _line(node: ast.AST) -> int | None:
    return getattr(node, "lineno", None)


def _forbidden(node: ast.AST, reason: str) -> ProgramError:
    line = _line(node)
    prefix = f"line {line}: " if line is not None else ""
    return ProgramError(ErrorKind.FORBIDDEN, prefix + reason, line)


def _is_dunder(name: str) -> bool:
    return name.startswith("__")


def _declaration(tree: ast.Module) -> tuple[ast.Name, str] | None:
    """The target and text of a leading ``description = '<string literal>'`` statement, if any."""
    first = tree.body[0] if tree.body else None
    if (
        isinstance(first, ast.Assign)
        and len(first.targets) == 1
        and isinstance(first.targets[0], ast.Name)
        and first.targets[0].id == DECLARABLE_NAME
        and isinstance(first.value, ast.Constant)
        and isinstance(first.value.value, str)
    ):
        return first.targets[0], first.value.value
    return None


def declared_description(source: str) -> str | None:
    """The string a program assigns to ``description`` in its first statement (RefAV style), if any.

    Only a plain string literal counts (``description = 'vehicle turning left'``); a program
    that does not parse, or starts otherwise, declares none.
    """
    try:
        tree = ast.parse(source, filename=PROGRAM_FILENAME, mode="exec")
    except (SyntaxError, ValueError, RecursionError, MemoryError):
        return None
    found = _declaration(tree)
    return None if found is None else found[1]


def check_program(
    source: str,
    config: SandboxConfig | None = None,
    functions: Collection[str] | None = None,
) -> ProgramError | None:
    """Check a program against the whitelist without running it.

    Args:
        source: the program text.
        config: size limits; defaults to :class:`SandboxConfig`.
        functions: names of the callable mining functions; defaults to every DSL function.

    Returns:
        ``None`` if the program may run, else the first problem found (``syntax`` or ``forbidden``).
    """
    cfg = config or SandboxConfig()
    if not isinstance(source, str):
        return ProgramError(ErrorKind.SYNTAX, f"the program must be text, got {type(source).__name__}")
    if len(source) > cfg.max_program_chars:
        return ProgramError(
            ErrorKind.FORBIDDEN,
            f"the program has {len(source)} characters; at most {cfg.max_program_chars} are allowed",
        )
    try:
        tree = ast.parse(source, filename=PROGRAM_FILENAME, mode="exec")
    except SyntaxError as exc:
        return ProgramError(ErrorKind.SYNTAX, f"line {exc.lineno}: {exc.msg}", exc.lineno)
    except (ValueError, RecursionError, MemoryError) as exc:
        return ProgramError(ErrorKind.SYNTAX, f"the program cannot be parsed ({type(exc).__name__}: {exc})")

    allowed_funcs = frozenset(functions) if functions is not None else frozenset(DSL_FUNCTIONS)
    known = allowed_funcs | SAFE_BUILTIN_NAMES | PREDEFINED_NAMES
    nodes = list(ast.walk(tree))
    if len(nodes) > cfg.max_ast_nodes:
        return ProgramError(
            ErrorKind.FORBIDDEN,
            f"the program has {len(nodes)} syntax nodes; at most {cfg.max_ast_nodes} are allowed",
        )
    assigned = {n.id for n in nodes if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Store)}
    found = _declaration(tree)
    declaration = None if found is None else found[0]

    for node in nodes:
        reason = _FORBIDDEN_REASONS.get(type(node))
        if reason is not None:
            return _forbidden(node, reason)
        if not isinstance(node, _ALLOWED_NODES):
            return _forbidden(node, f"{type(node).__name__} is not allowed in mining programs")
        if isinstance(node, ast.Name):
            if _is_dunder(node.id):
                return _forbidden(node, f"the name {node.id!r} is not allowed (no names starting with '__')")
            if (
                isinstance(node.ctx, ast.Store)
                and node.id in PREDEFINED_NAMES | allowed_funcs
                and node is not declaration
            ):
                hint = (
                    " (only a first line description = '<text>' with a plain string may set it)"
                    if node.id == DECLARABLE_NAME
                    else ""
                )
                return _forbidden(node, f"do not assign to {node.id!r}; it is predefined{hint}")
            if isinstance(node.ctx, ast.Load) and node.id not in known and node.id not in assigned:
                hint = _DENIED_CALL_HINTS.get(node.id) or (
                    "it is neither a mining function, an allowed builtin, nor a variable the program assigns"
                )
                return _forbidden(node, f"the name {node.id!r} cannot be used: {hint}")
        elif isinstance(node, ast.Attribute):
            if _is_dunder(node.attr) or node.attr.startswith("_"):
                return _forbidden(
                    node, f"the attribute {node.attr!r} is not allowed (no attributes starting with '_')"
                )
            if not isinstance(node.ctx, ast.Load):
                return _forbidden(node, "assigning to attributes is not allowed")
            qualified = isinstance(node.value, ast.Name) and (node.value.id, node.attr) in ALLOWED_QUALIFIED
            if not qualified and node.attr not in ALLOWED_ATTRIBUTES:
                return _forbidden(
                    node,
                    f"the attribute '.{node.attr}' is not allowed; mining programs only call the mining "
                    "functions directly (np.inf and inf are available)",
                )
        elif isinstance(node, ast.Call):
            problem = _check_call(node, known, assigned)
            if problem is not None:
                return problem
            fault = check_call_arguments(node, DSL_FUNCTIONS)
            if fault is not None:
                return _forbidden(*fault)
        elif isinstance(node, ast.Constant) and isinstance(node.value, bytes):
            return _forbidden(node, "bytes literals are not allowed")
    return None


def _check_call(node: ast.Call, known: frozenset[str], assigned: set[str]) -> ProgramError | None:
    func = node.func
    if isinstance(func, ast.Name):
        return None  # names are checked on their own (unknown names get a specific message)
    if isinstance(func, ast.Call) and isinstance(func.func, ast.Name):
        if func.func.id in ("scenario_not", "reverse_relationship"):
            return None
        return _forbidden(
            node, "only scenario_not(...)(...) and reverse_relationship(...)(...) may be called twice"
        )
    if isinstance(func, ast.Attribute):
        return None  # attributes are whitelisted separately
    return _forbidden(node, "only mining functions and allowed builtins may be called")
