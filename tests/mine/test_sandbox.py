"""The program sandbox: hostile programs are refused or stopped with the right error kind, and the
test process survives; legitimate programs give the same scenario in the child as in process."""

from __future__ import annotations

import os
import signal
from pathlib import Path

import numpy as np
import pytest
from mining_scenes import T_S, Obj, const, make_log

from scenariominer.config.mining import MiningConfig, SandboxConfig
from scenariominer.mine.context import LogContext
from scenariominer.mine.sandbox import (
    ErrorKind,
    ProgramError,
    check_program,
    declared_description,
    run_program,
    run_trusted_program,
)
from scenariominer.mine.sandbox.process import _exit_error

GOOD = """
vehicles = get_objects_of_category(log_dir, category='VEHICLE')
bicycles = get_objects_of_category(log_dir, category='BICYCLE')
result = has_objects_in_relative_direction(vehicles, bicycles, log_dir, direction='right')
output_scenario(result, description, log_dir, output_dir)
"""

LIMITS = MiningConfig(sandbox=SandboxConfig(timeout_s=1.5, memory_mb=512, cpu_s=20))
MEMORY_LIMITS = MiningConfig(sandbox=SandboxConfig(timeout_s=30.0, memory_mb=512, cpu_s=20))


@pytest.fixture(scope="module")
def ctx() -> LogContext:
    """Ego with a bicycle beside it (so GOOD has a non-empty answer); no map."""
    zero = const(0.0)
    objs = [
        Obj("ego", "EGO_VEHICLE", 10 * T_S, zero, zero),
        Obj("bike", "BICYCLE", 10 * T_S, const(-3.0), zero, 1.8, 0.6),
        Obj("ped", "PEDESTRIAN", const(30.0), const(8.0), zero, 0.5, 0.5),
    ]
    return LogContext(make_log(objs, log_id="sandbox"), LIMITS)


@pytest.fixture(scope="module", autouse=True)
def warm_forkserver(ctx: LogContext) -> None:
    """Start the sandbox's process server once (it imports the predicate library)."""
    assert run_program(GOOD, ctx, config=MiningConfig()).ok


# ---------------------------------------------------------------------- refused before running

FORBIDDEN = {
    "import": "import os",
    "import_from": "from os import system",
    "dunder_import": "__import__('os').system('echo owned')",
    "subclasses_walk": "().__class__.__bases__[0].__subclasses__()",
    "subclasses_comprehension": "x = [c for c in ().__class__.__base__.__subclasses__()]",
    "open": "open('/etc/passwd').read()",
    "eval": "eval('1 + 1')",
    "exec": "exec('import os')",
    "compile": "compile('1', 'f', 'exec')",
    "getattr": "getattr(log_dir, '__class__')",
    "setattr": "setattr(log_dir, 'log', None)",
    "globals": "globals()['__builtins__']",
    "locals": "locals()",
    "vars": "vars(log_dir)",
    "breakpoint": "breakpoint()",
    "input": "input()",
    "type": "type(log_dir)",
    "while_true": "while True:\n    pass",
    "recursion_bomb": "def f():\n    return f()\nf()",
    "lambda": "f = lambda: 0",
    "class": "class A:\n    pass",
    "decorator": "@scenario_not\ndef f(x):\n    return x",
    "async_def": "async def f():\n    pass",
    "format_string_attribute": "'{0.__class__}'.format(log_dir)",
    "fstring_dunder": "x = f'{log_dir.__class__}'",
    "generator_frame": "g = (x for x in [1])\nframe = g.gi_frame.f_back",
    "frame_attribute": "x = [1].gi_frame",
    "private_attribute": "x = log_dir._memo",
    "public_attribute_of_context": "x = log_dir.log.map_dir",
    "builtins_modification": "__builtins__['len'] = print",
    "os_module": "os.system('ls')",
    "subprocess_module": "subprocess.run(['ls'])",
    "sys_modules": "x = sys.modules",
    "function_globals": "x = scenario_not.__globals__",
    "wrapped_attribute": "x = reverse_relationship(near_objects).__wrapped__",
    "numpy_escape": "x = np.random",
    "global": "global x",
    "nonlocal_in_def": "def f():\n    nonlocal x",
    "try_except": "try:\n    x = 1\nexcept Exception:\n    pass",
    "with": "with open('x') as fh:\n    pass",
    "delete": "del log_dir",
    "rebind_predefined": "log_dir = 1",
    "rebind_predefined_first": "output_dir = 'x'",
    "description_not_first": "x = 1\ndescription = 'late'",
    "description_twice": "description = 'a'\ndescription = 'b'",
    "description_augmented": "description = 'a'\ndescription += 'b'",
    "description_fstring": "description = f'{log_dir}'",
    "description_call": "description = str(1)",
    "description_number": "description = 1",
    "description_tuple": "description, x = 'a', 1",
    "description_chained": "description = x = 'a'",
    "description_annotated": "description: str = 'a'",
    "description_loop": "for description in ['a']:\n    pass",
    "rebind_function": "stationary = print",
    "walrus": "y = (x := 1)",
    "raise": "raise SystemExit",
    "bytes_literal": "x = b'payload'",
    "call_through_subscript": "x = [print][0]('hi')",
    "too_long": "x = 1\n" * 5000,
}


@pytest.mark.parametrize("name", sorted(FORBIDDEN))
def test_hostile_program_is_refused_before_running(ctx: LogContext, name: str) -> None:
    problem = check_program(FORBIDDEN[name])
    assert problem is not None and problem.kind is ErrorKind.FORBIDDEN, problem
    result = run_program(FORBIDDEN[name], ctx)
    assert not result.ok and result.error == problem and result.elapsed_s < 1.0


@pytest.mark.parametrize(
    "source",
    ["x = (1 + ", "(" * 300 + "1" + ")" * 300, "def f(:\n  pass", "x = 1\n  y = 2"],
    ids=["unclosed", "nested_300", "bad_def", "indent"],
)
def test_invalid_python_is_a_syntax_error_with_a_line(source: str) -> None:
    problem = check_program(source)
    assert problem is not None and problem.kind is ErrorKind.SYNTAX


def test_messages_name_the_line_and_cause() -> None:
    problem = check_program("vehicles = get_objects_of_category(log_dir, 'VEHICLE')\nx = open('f')\n")
    assert problem == ProgramError(
        ErrorKind.FORBIDDEN,
        "line 2: the name 'open' cannot be used: it is not available to mining programs",
        2,
    )
    assert problem.feedback().startswith("forbidden error: line 2:")


def test_size_limits_come_from_the_config() -> None:
    assert check_program("x = 1\n" * 50, SandboxConfig(max_program_chars=100)).kind is ErrorKind.FORBIDDEN  # type: ignore[union-attr]
    nodes = check_program("x = [1, 2, 3, 4, 5, 6]", SandboxConfig(max_ast_nodes=5))
    assert nodes is not None and "syntax nodes" in nodes.message
    assert check_program(GOOD) is None


# ---------------------------------------------------------------------- stopped while running

STOPPED = {
    "list_of_10e10": ("x = [0] * 10**10", ErrorKind.MEMORY),
    "string_of_10e12": ("x = 'a' * 10**12", ErrorKind.MEMORY),
    "gradual_allocation": ("x = [[0] * 10**6 for _ in range(10**4)]", ErrorKind.MEMORY),
    "huge_power": ("x = 10 ** 10 ** 9", ErrorKind.TIMEOUT),
    # busy without allocating (the filter keeps nothing), so only the time limit can stop it: no race
    # with the memory limit
    "busy_comprehension": ("x = [a for a in range(10**5) for b in range(10**5) if a < 0]", ErrorKind.TIMEOUT),
    "long_range": ("x = list(range(10**9))", ErrorKind.RUNTIME),
    "division_by_zero": ("x = 1 / 0", ErrorKind.RUNTIME),
    "wrong_arguments": (
        "k = 'fast'\nx = has_velocity(log_dir=log_dir, track_candidates=[], min_velocity=k)",
        ErrorKind.RUNTIME,
    ),
    "map_predicate_without_map": (
        "v = get_objects_of_category(log_dir, 'VEHICLE')\noutput_scenario(on_road(v, log_dir), description)",
        ErrorKind.RUNTIME,
    ),
    "no_output": ("x = get_objects_of_category(log_dir, 'VEHICLE')", ErrorKind.INVALID_OUTPUT),
    "output_not_a_scenario": ("output_scenario([1, 2, 3], description)", ErrorKind.INVALID_OUTPUT),
    "output_twice": (
        "v = get_objects_of_category(log_dir, 'VEHICLE')\n"
        "output_scenario(v, description)\noutput_scenario(v, description)",
        ErrorKind.INVALID_OUTPUT,
    ),
    "print_only": ("print(log_dir)", ErrorKind.INVALID_OUTPUT),
}


@pytest.mark.parametrize("name", sorted(STOPPED))
def test_hostile_program_is_stopped_with_the_right_kind(ctx: LogContext, name: str) -> None:
    source, kind = STOPPED[name]
    assert check_program(source) is None  # these pass the static checks
    # A program that must hit the memory limit gets a generous time limit, so a slow (loaded)
    # machine cannot make the timeout fire first: only the limit under test can stop it.
    config = MEMORY_LIMITS if kind is ErrorKind.MEMORY else LIMITS
    result = run_program(source, ctx, config=config)
    assert not result.ok and result.error is not None and result.error.kind is kind, result.error
    assert result.elapsed_s < config.sandbox.timeout_s + 3.0


def test_runtime_errors_point_at_the_failing_line(ctx: LogContext) -> None:
    source = "v = get_objects_of_category(log_dir, 'VEHICLE')\nk = 'x'\n"
    source += "x = has_velocity(v, log_dir, min_velocity=k)\n"  # a variable: only running it can tell
    result = run_program(source, ctx)
    assert result.error is not None and result.error.line == 3
    assert result.error.message.startswith("line 3: TypeError: has_velocity(): min_velocity must be a number")
    no_map = run_program(STOPPED["map_predicate_without_map"][0], ctx)
    assert no_map.error is not None and "on_road() needs an HD map" in no_map.error.message


def test_cpu_limit_stops_a_busy_program(ctx: LogContext) -> None:
    cfg = MiningConfig(sandbox=SandboxConfig(timeout_s=30.0, cpu_s=1))
    result = run_program(STOPPED["busy_comprehension"][0], ctx, config=cfg)
    assert result.error is not None and result.error.kind is ErrorKind.TIMEOUT
    assert "CPU time" in result.error.message


def test_memory_limit_comes_from_the_config(ctx: LogContext) -> None:
    source = "x = [0] * (40 * 10**6)\n" + GOOD  # about 320 MB
    assert run_program(source, ctx, config=MiningConfig(sandbox=SandboxConfig(memory_mb=1024))).ok
    small = run_program(source, ctx, config=MiningConfig(sandbox=SandboxConfig(memory_mb=100)))
    assert small.error is not None and small.error.kind is ErrorKind.MEMORY


def test_range_cap_comes_from_the_config(ctx: LogContext) -> None:
    cfg = MiningConfig(sandbox=SandboxConfig(max_range_len=10))
    result = run_program("x = range(11)\n" + GOOD, ctx, config=cfg)
    assert result.error is not None and "at most 10" in result.error.message
    assert run_program("x = range(10)\n" + GOOD, ctx, config=cfg).ok


def test_exit_codes_of_dead_children_are_explained() -> None:
    assert _exit_error(-signal.SIGXCPU).kind is ErrorKind.TIMEOUT
    assert _exit_error(-signal.SIGKILL).kind is ErrorKind.MEMORY
    assert "SIGSEGV" in _exit_error(-signal.SIGSEGV).message
    assert "exit code 3" in _exit_error(3).message


# ---------------------------------------------------------------------- legitimate programs


def test_child_and_in_process_runs_agree(ctx: LogContext) -> None:
    child = run_program(GOOD, ctx, description="vehicle with a bicycle to its right")
    local = run_trusted_program(GOOD, ctx, description="vehicle with a bicycle to its right")
    assert child.ok and local.ok and child.scenario is not None and local.scenario is not None
    assert np.array_equal(child.scenario.referred, local.scenario.referred)
    assert np.array_equal(child.scenario.relations, local.scenario.relations)
    assert child.scenario.context is ctx and child.description == "vehicle with a bicycle to its right"
    assert list(child.scenario) == ["ego"]


#: A program as RefAV writes them (RefAV ``exec``s it with ``log_dir`` and ``output_dir`` defined).
REFAV_PROGRAM = """description = 'vehicle with a bicycle on its right'
vehicles = get_objects_of_category(log_dir, category="VEHICLE")
bicycles = get_objects_of_category(log_dir, category="BICYCLE")
vehicles_with_bicycle_right = has_objects_in_relative_direction(
    vehicles, bicycles, log_dir, direction='right', within_distance=5)
output_scenario(vehicles_with_bicycle_right, description, log_dir, output_dir)
"""


def test_refav_programs_run_unchanged_with_their_own_description(ctx: LogContext) -> None:
    assert check_program(REFAV_PROGRAM) is None
    assert declared_description(REFAV_PROGRAM) == "vehicle with a bicycle on its right"
    assert declared_description(GOOD) is None and declared_description("x = (") is None
    for run in (run_program, run_trusted_program):
        result = run(REFAV_PROGRAM, ctx, description="the query")
        assert result.ok, result.error
        assert result.description == "vehicle with a bicycle on its right"
        assert result.scenario is not None and list(result.scenario) == ["ego"]
    # the exception is for that one statement: later, the name is predefined as before
    problem = check_program(REFAV_PROGRAM + "description = 'again'\n")
    assert problem is not None and problem.line == 7
    assert "only a first line description = '<text>'" in problem.message


def test_mine_runs_a_refav_program_file(tmp_path: Path, av2_log_dir: Path) -> None:
    from typer.testing import CliRunner

    from scenariominer.cli import app

    prog = tmp_path / "refav_program.txt"
    prog.write_text(REFAV_PROGRAM, encoding="utf-8")
    res = CliRunner().invoke(
        app,
        ["mine", "vehicle with a bicycle on its right", "--logs", str(av2_log_dir), "--program", str(prog)],
    )
    assert res.exit_code == 0, res.output
    assert "program ok (given" in res.output and "1 log(s) match, 0 failed" in res.output


def test_programs_may_use_loops_containers_and_constants(ctx: LogContext) -> None:
    source = """
names = ['VEHICLE', 'BICYCLE']
groups = {}
for name in names:
    groups[name] = get_objects_of_category(log_dir, category=name)
picked = [groups[k] for k in sorted(groups.keys()) if len(groups[k]) > 0]
assert len(picked) == 2
both = scenario_or(picked)
near = near_objects(both, groups.get('BICYCLE'), log_dir, distance_thresh=np.inf)
print('debug output is discarded')
output_scenario(near, description, log_dir, output_dir)
"""
    result = run_program(source, ctx)
    assert result.ok, result.error
    assert result.scenario is not None and set(result.scenario) == {"ego"}


def test_the_host_survives_and_the_sandbox_keeps_working(ctx: LogContext) -> None:
    pid = os.getpid()
    for source, kind in STOPPED.values():
        if kind is not ErrorKind.TIMEOUT:  # the timeouts are exercised above
            run_program(source, ctx)
    assert os.getpid() == pid
    assert run_program(GOOD, ctx).ok
