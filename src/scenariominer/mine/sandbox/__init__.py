"""Checking and running mining programs: an AST whitelist, then a resource-limited child process.

A mining program is a short Python text written by a language model (or a person) that calls
the functions of :mod:`scenariominer.mine.dsl` and ends with
``output_scenario(scenario, description, log_dir, output_dir)`` (RefAV's convention). The
program sees these predefined variables:

* ``log_dir``: the log being mined (a :class:`~scenariominer.mine.context.LogContext`; ``log`` is
  an alias), passed wherever RefAV passes its log folder;
* ``description``: the natural-language description being mined;
* ``output_dir``: ``None`` (accepted by ``output_scenario`` for compatibility);
* ``inf``; and ``np.inf``/``np.pi``/``math.inf``/``math.pi`` as the only attributes of ``np``/``math``.

Untrusted programs go through two barriers:

1. :func:`check_program` parses the text with :mod:`ast` and refuses, before anything runs,
   every construct outside a small whitelist: imports, function/class/lambda definitions,
   ``while`` loops, ``try``/``with``/``raise``/``global``/``nonlocal``/``del``, generators and
   ``await``, any name or attribute starting with ``__``, any attribute except a handful of
   container methods and ``np.inf``-style constants, and any name that is neither a mining
   function, a safe builtin (``len min max range abs sorted list dict set tuple enumerate zip
   bool int float str sum any all round print``), a predefined variable, nor assigned by the
   program itself; predefined names and mining functions cannot be reassigned. There is
   therefore no route to ``__class__``/``__subclasses__``, ``__globals__``, frames
   (``gi_frame``), ``str.format`` field look-ups, ``open``, ``eval``, ``exec``, ``getattr`` or
   modules. One assignment to a predefined name is allowed, for RefAV programs, which all begin
   with ``description = '...'``: a FIRST statement assigning a plain string literal to
   ``description``; the program then sees (and passes to ``output_scenario``) that description,
   as in RefAV, and :func:`declared_description` reads it. Definitions are refused rather than
   checked because mining programs are straight-line compositions: allowing ``def``/``lambda``
   would only add recursion and hidden control flow.
2. :func:`run_program` executes the checked program in a separate process (``forkserver``,
   preloaded with the predicate library) with an address-space limit (``RLIMIT_AS``), a CPU
   limit, no file writes (``RLIMIT_FSIZE = 0``) and a wall-clock deadline enforced by the host,
   which kills the child. The child returns plain bytes (a JSON header and raw arrays), never a
   pickle, so even a compromised child cannot run code in the host.

Failures come back as a :class:`ProgramError` whose ``kind`` is one of :class:`ErrorKind`
(syntax, forbidden, runtime, timeout, memory, invalid_output) and whose message names the
line and the cause in words suited to feed back to a language model.

:func:`run_trusted_program` is the in-process fast path for TRUSTED, hand-written programs
(the example bank, benchmarks): same checks and namespace, no child process and no limits.
"""

from __future__ import annotations

from scenariominer.mine.sandbox.check import (
    ALLOWED_ATTRIBUTES,
    PREDEFINED_NAMES,
    SAFE_BUILTIN_NAMES,
    ErrorKind,
    ProgramError,
    ProgramResult,
    check_program,
    declared_description,
)
from scenariominer.mine.sandbox.execute import (
    run_trusted_program,
)
from scenariominer.mine.sandbox.process import (
    run_program,
)

__all__ = [
    "ALLOWED_ATTRIBUTES",
    "PREDEFINED_NAMES",
    "SAFE_BUILTIN_NAMES",
    "ErrorKind",
    "ProgramError",
    "ProgramResult",
    "check_program",
    "declared_description",
    "run_program",
    "run_trusted_program",
]
