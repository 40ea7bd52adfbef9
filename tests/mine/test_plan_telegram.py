"""Telegram-style requests in the words the phrase tables read (mine/plan_telegram.py)."""

from __future__ import annotations

import pytest
from plan_checks import assert_program_has

from scenariominer.mine.plan_telegram import telegram_wording


@pytest.mark.parametrize(
    ("telegram", "calls"),
    [
        # the word ending each sentence asks for nothing stopped
        ("NEED ALL BUSES TURNING LEFT STOP ADVISE SOONEST STOP", ["category='BUS'", "direction='left'"]),
        (
            "FIND TRUCKS CHANGING LANES EITHER DIRECTION STOP SEND TIMES STOP",
            ["changing_lanes(subject, log_dir)"],
        ),
        # a later sentence that bounds a value defines the first one's vague word
        (
            "SEEK CARS BRAKING HARD STOP DECELERATION BEYOND 3 METRES PER SECOND SQUARED STOP",
            ["accelerating(subject, log_dir, min_accel=-inf, max_accel=-3)"],
        ),
        ("CARS HALTED NOT PARKED STOP SPEED UNDER HALF METRE PER SECOND STOP", ["max_velocity=0.5"]),
        # articles dropped
        ("REQUEST VANS FOLLOWING EGO SAME LANE STOP", ["following(subject, related_1, log_dir)"]),
        ("WANT BUSES MAKING RIGHT TURN STOP", ["direction='right'"]),
        ("LOCATE PEDESTRIANS SEEN IN LOG STOP", ["category='PEDESTRIAN'"]),
        # a stop sign is a sign
        ("FIND CARS NEAR STOP SIGN STOP", ["at_stop_sign("]),
    ],
)
def test_a_telegram_is_read_in_full(telegram: str, calls: list[str]) -> None:
    program = assert_program_has(telegram, calls)
    if "STOP SIGN" not in telegram:
        assert "stationary" not in program or "PARKED" in telegram


def test_a_telegram_keeps_its_request_and_the_bounds_after_it() -> None:
    assert telegram_wording("FIND PARKED VEHICLES STOP UNMOVED ENTIRE LOG STOP") == "find parked vehicles"
    assert telegram_wording("MOVING BUSES STOP SPEED OVER 1 METRE PER SECOND STOP") == (
        "moving buses (speed over 1 metre per second)"
    )


@pytest.mark.parametrize(
    "text",
    [
        "find vehicles near a stop sign",  # not in capitals
        "FIND STOPPED CARS",  # no final STOP
        "Find the cars that come to a STOP at a light, then STOP",  # mostly lower case
    ],
)
def test_text_that_is_no_telegram_comes_back_unchanged(text: str) -> None:
    assert telegram_wording(text) == text
