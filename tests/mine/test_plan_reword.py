"""The rewording step (mine/plan_reword.py): the model puts a description in plain words.

Checks of a rewording against its description, the step inside the synthesizer with a scripted
model (when it is asked, what happens when it is refused), and one call of the real model.
"""

from __future__ import annotations

import pytest

from scenariominer.config.mining import GenerationConfig
from scenariominer.llm.cache import resolve_cache_dir
from scenariominer.llm.client import ChatClient
from scenariominer.llm.llamacpp import LlamaCppBackend
from scenariominer.llm.model_files import ModelNotAvailableError, ensure_model_file
from scenariominer.mine.plan import plan_text
from scenariominer.mine.plan_prompts import REWORD_EXAMPLES
from scenariominer.mine.plan_reader import read_plan
from scenariominer.mine.plan_reword import (
    REWORD_GRAMMAR,
    _numbers,
    reword,
    reword_again,
    reword_messages,
    reworded_plan,
)
from scenariominer.mine.synthesis import ProgramSynthesizer
from scenariominer.testing import ScriptedBackend

#: Not read in full by the phrase rules (a register they have not met); subject read.
ODD = "vehicles, kindly surface each one that is doing the 'sudden stop' routine within 15 m of us"


def test_every_worked_example_of_the_prompt_is_read_in_full_by_the_rules() -> None:
    for odd, plain in REWORD_EXAMPLES:
        assert read_plan(plain) is not None, plain
        assert reworded_plan(odd, plain)[0] is not None, (odd, plain)


def test_the_odd_wording_of_these_tests_is_not_read_in_full() -> None:
    assert read_plan(ODD) is None


def test_a_rewording_that_keeps_numbers_and_road_users_is_read_and_kept_in_the_plan() -> None:
    plan, reason = reworded_plan(ODD, "vehicles braking hard within 15 m of the ego vehicle")
    assert reason == ""
    assert plan is not None
    assert plan["reworded"] == "vehicles braking hard within 15 m of the ego vehicle"
    assert plan["subject_category"] == "VEHICLE"
    assert "- read as (the model's plain rewording): vehicles braking hard" in plan_text(plan)


@pytest.mark.parametrize(
    ("rewording", "why"),
    [
        ("vehicles braking hard near the ego vehicle", "changes the numbers stated"),  # 15 dropped
        ("vehicles braking hard within 10 m of the ego vehicle", "changes the numbers stated"),
        ("vehicles braking at over 3 m/s^2 within 15 m of the ego vehicle", "changes the numbers stated"),
        ("pedestrians within 15 m of the ego vehicle", "a road user the description does not name"),
        ("vehicles doing a sudden-stop routine within 15 m of us", "cannot read the rewording in full"),
        ("", "no rewording"),
    ],
)
def test_a_rewording_that_changes_the_request_is_refused_with_its_reason(rewording: str, why: str) -> None:
    plan, reason = reworded_plan(ODD, rewording)
    assert plan is None
    assert why in reason


def test_a_group_may_narrow_to_a_member_but_a_member_may_not_widen_to_its_group() -> None:
    assert reworded_plan("vehicles doing the 'sudden stop' routine", "cars braking hard")[0] is not None
    assert reworded_plan("cars doing the 'sudden stop' routine", "vehicles braking hard")[0] is None


def test_number_words_count_as_the_numbers_they_name() -> None:
    plain = "pedestrians within 5 m of the ego vehicle"
    plan, reason = reworded_plan("peds, um, five metres-ish from our car", plain)
    assert reason == "" and plan is not None


@pytest.mark.parametrize(
    ("text", "numbers"),
    [
        ("trucks within 10m of us", {10.0}),  # a unit run into its number
        ("braking at 1.5 m/s^2 or m/s²", {1.5}),  # no exponent
        ("[S3, E4] the 3rd car behind a 2-wheeled cart", set()),  # no rating, ordinal or compound
    ],
)
def test_which_numbers_a_rewording_must_keep(text: str, numbers: set[float]) -> None:
    assert _numbers(text) == numbers


def test_what_the_rewording_says_is_done_with_the_result_is_not_read() -> None:
    description = "Given a pedestrian When they walk in a bike lane Then the pedestrian is flagged"
    for said in ("", " flagged", " are returned", ", reported", " should be returned"):
        plan, reason = reworded_plan(description, "pedestrians walking in a bike lane" + said)
        assert reason == "" and plan is not None, said
        assert plan["reworded"] == "pedestrians walking in a bike lane" + said  # shown as the model said it


def test_the_request_shows_the_worked_examples_as_turns_then_the_description() -> None:
    messages = reword_messages(ODD)
    assert messages[0].role == "system"
    assert [m.content for m in messages[1:-1:2]] == [odd for odd, _ in REWORD_EXAMPLES]
    assert [m.content for m in messages[2:-1:2]] == [plain for _, plain in REWORD_EXAMPLES]
    assert messages[-1].content == ODD


def test_reword_keeps_the_first_line_single_spaced_and_decodes_under_the_grammar() -> None:
    backend = ScriptedBackend(["  vehicles   braking hard\nwithin 15 m\n"])
    assert reword(ChatClient(backend), ODD) == "vehicles braking hard"
    assert backend.requests[0].grammar == REWORD_GRAMMAR


def _synth(replies: list[str], **config: bool | int) -> tuple[ProgramSynthesizer, ScriptedBackend]:
    backend = ScriptedBackend(replies)
    return ProgramSynthesizer(ChatClient(backend), None, GenerationConfig(**config)), backend


def test_the_synthesizer_asks_for_a_rewording_only_when_the_rules_cannot_read_the_description() -> None:
    synth, backend = _synth(["vehicles braking hard within 15 m of the ego vehicle"])
    assert synth.plan_for("vehicles braking hard") is not None  # read in full: no call
    assert backend.requests == []
    plan = synth.plan_for(ODD)
    assert plan is not None and plan["reworded"] == "vehicles braking hard within 15 m of the ego vehicle"
    assert len(backend.requests) == 1
    assert synth.rewordings[ODD]["refused"] == ""
    assert synth.plan_for(ODD) is plan and len(backend.requests) == 1  # kept per description


def test_a_refused_rewording_leaves_the_partial_reading_and_says_why() -> None:
    synth, backend = _synth(["pedestrians within 15 m of the ego vehicle"], plan_reword_tries=1)
    plan = synth.plan_for(ODD)
    assert plan is not None and "reworded" not in plan
    assert plan["unread"]  # the rules' partial reading of the description itself
    assert "does not name" in synth.rewordings[ODD]["refused"]
    assert len(backend.requests) == 1


def test_a_second_request_shows_the_rewording_and_the_words_the_rules_left_out() -> None:
    refused = "vehicles doing a sudden-stop routine within 15 m of us"
    backend = ScriptedBackend(["vehicles braking hard within 15 m of the ego vehicle"])
    again, hint = reword_again(ChatClient(backend), ODD, refused)
    assert again == "vehicles braking hard within 15 m of the ego vehicle"
    assert hint == "Simpler, please: without the words 'doing', 'sudden-stop', 'routine'."
    request = backend.requests[0]
    assert request.grammar == REWORD_GRAMMAR
    assert [m.content for m in request.messages[-2:]] == [refused, hint]
    assert request.messages[-2].role == "assistant" and request.messages[-1].role == "user"
    assert [m.content for m in request.messages[:-2]] == [m.content for m in reword_messages(ODD)]


@pytest.mark.parametrize(
    ("description", "rewording"),
    [
        (ODD, "vehicles braking hard within 15 m of the ego vehicle"),  # it passes
        # a changed negation: told to keep it, the model negated the wrong word
        ("cars that do not move the whole time, i.e. parked", "parked cars"),
        (ODD, "vehicles braking hard near the ego vehicle"),  # a number dropped
        (ODD, "pedestrians within 15 m of the ego vehicle"),  # another road user
        (ODD, "braking hard within 15 m of us"),  # no subject read: asked for one, it said "road users"
    ],
)
def test_no_second_request_unless_the_rules_read_the_rewording_in_part(
    description: str, rewording: str
) -> None:
    backend = ScriptedBackend([])
    assert reword_again(ChatClient(backend), description, rewording) == ("", "")
    assert backend.requests == []


def test_the_synthesizer_uses_the_second_rewording_when_the_first_is_refused() -> None:
    synth, backend = _synth(
        [
            "vehicles doing a sudden-stop routine within 15 m of us",
            "vehicles braking hard within 15 m of the ego vehicle",
        ]
    )
    plan = synth.plan_for(ODD)
    assert plan is not None and plan["reworded"] == "vehicles braking hard within 15 m of the ego vehicle"
    assert len(backend.requests) == 2
    assert synth.rewordings[ODD] == {
        "text": "vehicles braking hard within 15 m of the ego vehicle",
        "refused": "",
        "earlier": "vehicles doing a sudden-stop routine within 15 m of us",
    }


def test_a_second_refused_rewording_leaves_the_partial_reading() -> None:
    synth, backend = _synth(
        ["vehicles doing a sudden-stop routine within 15 m of us", "vehicles doing the routine within 15 m"]
    )
    plan = synth.plan_for(ODD)
    assert plan is not None and "reworded" not in plan and plan["unread"]
    assert len(backend.requests) == 2
    assert "cannot read the rewording in full" in synth.rewordings[ODD]["refused"]


def test_with_plan_reword_off_no_rewording_is_asked_for() -> None:
    synth, backend = _synth([], plan_reword=False)
    plan = synth.plan_for(ODD)
    assert plan is not None and plan["unread"]
    assert backend.requests == [] and synth.rewordings == {}


@pytest.mark.slow
def test_the_embedded_model_rewords_an_odd_request_into_words_the_rules_read() -> None:
    try:
        model_file = ensure_model_file(resolve_cache_dir())
    except ModelNotAvailableError as exc:
        pytest.skip(f"bundled model not available: {exc}")
    backend = LlamaCppBackend(model_file, model_name="qwen2.5-coder-1.5b", n_ctx=8192)
    description = "Kindly surface every person on foot strolling across the street ahead of our car"
    try:
        rewording = reword(ChatClient(backend), description)
    finally:
        backend.close()
    assert read_plan(description) is None  # the rules alone cannot read it
    plan, reason = reworded_plan(description, rewording)
    assert reason == "", reason
    assert plan is not None and plan["subject_category"] == "PEDESTRIAN"


@pytest.mark.parametrize(
    ("description", "rewording"),
    [
        ("trackgrep --class regular-vehicle --min-speed 10", "regular vehicles moving faster than 10 m/s"),
        ("SELECT track FROM box_trucks WHERE parked", "parked box trucks"),
    ],
)
def test_a_road_user_named_with_a_hyphen_or_underscore_counts_as_named(
    description: str, rewording: str
) -> None:
    plan, reason = reworded_plan(description, rewording)
    assert reason == "" and plan is not None


def test_a_speed_unit_the_description_does_not_state_is_read_as_metres_per_second() -> None:
    plan, reason = reworded_plan(
        "class:REGULAR_VEHICLE AND speed:>15", "regular vehicles moving faster than 15 km/h"
    )
    assert reason == "" and plan is not None
    assert plan["conditions"][0]["argument"] == "min_velocity=15.0"
    assert plan["reworded"] == "regular vehicles moving faster than 15 m/s"  # shown as it was read
    plan, _ = reworded_plan("trucks > 30 km/h", "trucks moving faster than 30 km/h")  # stated: kept
    assert plan is not None and plan["conditions"][0]["argument"] == "min_velocity=8.33"


@pytest.mark.parametrize(
    ("description", "rewording", "used"),
    [
        (
            "ego AND left_side:REGULAR_VEHICLE AND dist<=4",
            "the ego vehicle with a regular vehicle within 4 m",
            False,
        ),
        ("Given a car When it turns right Then return it", "car turning left", False),
        (
            "car merging over, kinda rightwards",
            "car changing lanes to the right",
            True,
        ),  # "rightwards" names the side too
        (
            "Cones sitting right on the road #ConeZone",
            "construction cones on the road",
            True,
        ),  # an intensifier
        ("A car rolls right over the crosswalk!", "cars moving on a pedestrian crossing", True),
        (
            "Given a car When it turns right at a junction Then return it",
            "car turning right at an intersection",
            True,
        ),
    ],
)
def test_a_rewording_must_keep_the_sides_the_description_states(
    description: str, rewording: str, used: bool
) -> None:
    plan, reason = reworded_plan(description, rewording)
    assert (plan is not None) is used, reason
    if not used:
        assert "changes the sides stated" in reason


#: Not read by the phrase rules even in part (no road user first).
UNREAD = "yikes!! so much hard braking from the cars lol"


def test_a_description_not_even_read_in_part_gets_the_partial_reading_of_its_rewording() -> None:
    assert read_plan(UNREAD, partial=True) is None
    synth, backend = _synth(["cars braking hard in a weird way", "cars braking hard in a weird way again"])
    plan = synth.plan_for(UNREAD)
    assert plan is not None and plan["reworded"] == "cars braking hard in a weird way again"
    assert plan["subject_category"] == "REGULAR_VEHICLE" and plan["unread"] == ["in", "weird", "way", "again"]
    assert len(backend.requests) == 2  # the second request was made and refused first
    assert synth.rewordings[UNREAD]["in_part"] == "used"


def test_the_partial_reading_of_a_rewording_passes_the_same_checks() -> None:
    synth, backend = _synth(["trucks braking hard in a weird way"] + ["no plan"] * 5, plan_reword_tries=1)
    plan = synth.plan_for(UNREAD)
    assert plan is not None and "error" in plan  # left to the model's own plan (here no valid one)
    assert backend.requests[1].grammar != REWORD_GRAMMAR  # the plan request came next
    assert "does not name" in synth.rewordings[UNREAD]["in_part"]


def test_with_plan_partial_off_a_rewording_is_used_only_in_full() -> None:
    replies = ["cars braking hard in a weird way"] + ["no plan"] * 5
    synth, backend = _synth(replies, plan_reword_tries=1, plan_partial=False)
    plan = synth.plan_for(UNREAD)
    assert plan is not None and "error" in plan  # left to the model's own plan (here no valid one)
    assert backend.requests[1].grammar != REWORD_GRAMMAR
    assert "in_part" not in synth.rewordings[UNREAD]
