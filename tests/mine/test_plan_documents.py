"""Requests written as parameter blocks, ticket titles, tender clauses and in a child's words.

The wordings are my own, written for plan-reader/53 before the fresh57-fresh60 passes were read
(mine/plan_documents.py, and the child's words in mine/plan_registers.py); each must build the
program of its plain English.
"""

from __future__ import annotations

import pytest
from mining_scenes import rules_program

from scenariominer.mine.plan_documents import document_wording, yaml_block


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        ("actor: bus\nstate: stopped\nmap: near intersection", "buses stopped near an intersection"),
        ("target:\n  category: truck\n  motion: turning left", "trucks turning left"),
        ("category: PEDESTRIAN\non_road: false", "pedestrians not on the road"),
        ("category: REGULAR_VEHICLE\nchanging_lanes: left", "regular vehicles changing lanes to the left"),
        (
            "subject: vehicle\nlane: same as ego\nposition: ahead\nmax_distance_m: 20",
            "vehicles in the same lane as the ego vehicle and in front of the ego vehicle within 20 m",
        ),
        (
            "objects: [car, box truck]\nwithin_m: 10\nof: ego",
            "cars or box trucks within 10 m of the ego vehicle",
        ),
        ("{actor: pedestrian, on_road: true, speed_max_mps: 1}", "pedestrians on the road slower than 1 m/s"),
        ("actor: car\nmin_speed_kmh: 30\nlane: same as ego", "cars faster than 30 km/h in the ego's lane"),
        ("- actor: bus\n- stationary: true", "stationary buses"),
    ],
)
def test_a_parameter_block_builds_the_program_of_its_plain_english(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)


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
    ("written", "plain"),
    [
        ("Look for a car that turns left at a crossroads.", "cars turning left at an intersection"),
        ("Find a car that moves into another lane.", "cars changing lanes"),
        ("cars that stop for a long time", "stationary cars"),
        ("a car coming toward our car", "cars heading toward the ego vehicle"),
    ],
)
def test_a_childs_words_build_the_program_of_the_plain_english(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)


@pytest.mark.parametrize(
    "text",
    [
        "vehicles turning left",
        "3 pedestrians near the ego vehicle",
        "actor: vehicle; manoeuvre: right turn",
        "situation: a truck\nthat is very long and hard to describe in a key",
    ],
)
def test_text_that_is_no_such_document_is_unchanged(text: str) -> None:
    assert document_wording(yaml_block(text)) == text
