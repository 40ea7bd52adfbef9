"""Requests written as ticket titles and tender clauses (mine/plan_documents.py).

The first wordings are my own, written for plan-reader/53 before the fresh59 and fresh60 passes were
read; the later ones come from those spent runs. Each must build the program of its plain English.
"""

from __future__ import annotations

import pytest
from mining_scenes import rules_program

from scenariominer.mine.plan_documents import document_wording, request_text


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        (
            "[LBL-1021] [ped] [crossing] Tag pedestrians crossing in front of ego",
            "pedestrians crossing in front of ego",
        ),
        (
            "[DATA-88] [vehicle][lane-change] Find vehicles changing lanes to the left",
            "vehicles changing lanes left",
        ),
        (
            "MINE-301 [bus] [stopped] Label stationary buses near intersections",
            "stationary buses near intersections",
        ),
        ("QA-7: Flag trucks within 10 m of the ego vehicle", "trucks within 10 m of the ego vehicle"),
        ("ANN-556 [ego][turn] Find ego left turns", "the ego vehicle turning left"),
    ],
)
def test_a_ticket_title_builds_the_program_of_its_request(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        (
            "3.1 The Supplier shall identify all pedestrians crossing in front of the ego vehicle.",
            "pedestrians crossing in front of the ego vehicle",
        ),
        (
            "4.2.1 The Supplier shall deliver every instance of a vehicle changing lanes to the left.",
            "vehicles changing lanes to the left",
        ),
        (
            "The Contractor shall extract all occurrences wherein a bus is stationary within an"
            " intersection.",
            "buses stationary on an intersection",
        ),
        (
            "5.3 The Supplier shall provide each vehicle travelling in the same lane as, and ahead of,"
            " the ego vehicle at a distance not exceeding 25 metres.",
            "vehicles travelling in the same lane as the ego vehicle and in front of the ego vehicle"
            " within 25 m",
        ),
        (
            "R-12 The Supplier shall ensure that all trucks turning right are identified.",
            "trucks turning right",
        ),
        (
            "(b) The Supplier shall identify, together with the timestamps, all buses turning left",
            "buses turning left",
        ),
    ],
)
def test_a_tender_clause_builds_the_program_of_its_request(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)


@pytest.mark.parametrize(
    "text",
    [
        "vehicles turning left",
        "3 pedestrians near the ego vehicle",
        "actor: vehicle; manoeuvre: right turn",
    ],
)
def test_text_that_is_no_such_document_is_unchanged(text: str) -> None:
    assert document_wording(text) == text


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        # from the spent fresh59 and fresh60 runs (plan-reader/53): contract wording of a lane, a
        # place, a distance, a direction, a definition after its term
        (
            "1.1 The Supplier shall deliver every instance of a bus in a designated bus lane.",
            "buses on a bus lane",
        ),
        (
            "1.2 The Supplier shall deliver all pedestrians whose footprint overlaps a marked pedestrian"
            " crossing.",
            "pedestrians on a pedestrian crossing",
        ),
        (
            "1.5 The Supplier shall deliver all vehicles braking firmly, that is, decelerating at 2 m/s²"
            " or more.",
            "vehicles braking harder than 2 m/s²",
        ),
        (
            "1.6 The Supplier shall deliver all parked vehicles, meaning vehicles that remain in place for"
            " the entire recording.",
            "stationary vehicles",
        ),
        (
            "1.7 The Supplier shall deliver every vehicle that is momentarily halted in traffic, excluding"
            " vehicles parked for the whole log.",
            "vehicles momentarily halted in traffic but not parked",
        ),
        (
            "1.11 The Supplier shall deliver all vehicles travelling in the direction opposite to that of the"
            " ego vehicle.",
            "vehicles travelling in the opposite direction to the ego vehicle",
        ),
        (
            "1.19 The Supplier shall deliver all vehicles other than the ego vehicle that come within 20"
            " metres of the ego vehicle.",
            "vehicles other than the ego vehicle within 20 m of the ego vehicle",
        ),
        (
            "1.21 The Supplier shall deliver all vehicles, the ego vehicle excepted, that occupy the same"
            " lane as the ego vehicle.",
            "vehicles other than the ego vehicle in the same lane as the ego vehicle",
        ),
        (
            "1.34 The Supplier shall deliver all regular vehicles not located on a vehicle lane.",
            "cars not in a car lane",
        ),
        (
            "1.38 The Supplier shall deliver all vehicles heading toward the ego vehicle from no further than"
            " 25 metres away.",
            "vehicles heading toward the ego vehicle within 25 m",
        ),
        (
            "ANN-3127 [ped][facing] Pedestrians facing a vehicle 10 m away or closer",
            "pedestrians facing a vehicle within 10 m",
        ),
        (
            "ANN-3135 [vehicle][swerve] Vehicles swerving left at over 3 m/s² lateral",
            "vehicles swerving left with a lateral acceleration of more than 3 m/s²",
        ),
    ],
)
def test_contract_wording_builds_the_program_of_the_plain_english(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)


def test_a_definition_that_is_no_road_user_keeps_the_term() -> None:
    # ", meaning no other vehicle ..." defines a clear lane, not the subject: read by the phrase rules
    text = "moving vehicles with a clear lane ahead, meaning no other vehicle in front of them within 30 m"
    assert " i.e. " not in document_wording(text)


@pytest.mark.parametrize(
    ("written", "shown"),
    [
        (
            "1.38 The Supplier shall deliver all vehicles heading toward the ego vehicle.",
            "all vehicles heading toward the ego vehicle.",
        ),
        ("ANN-3135 [vehicle][swerve] Vehicles swerving left", "Vehicles swerving left"),
        ("3 pedestrians near the ego vehicle", "3 pedestrians near the ego vehicle"),
    ],
)
def test_the_model_is_shown_the_request_without_its_key_or_clause_number(written: str, shown: str) -> None:
    assert request_text(written) == shown
    # and so the request the model gets carries no clause number
    from scenariominer.mine.plan import plan_messages

    assert plan_messages(written)[-1].content.endswith(shown)
