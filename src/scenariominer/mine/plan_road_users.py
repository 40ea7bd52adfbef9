"""Road-user words of the phrase rules: each English phrase with the Argoverse 2 categories it names.

Read by :mod:`scenariominer.mine.plan_nouns` (the noun patterns) and
:mod:`scenariominer.mine.plan_reader` (a matched noun's categories); re-exported by
:mod:`scenariominer.mine.plan_phrases` with the other tables.
"""

from __future__ import annotations

__all__ = ["CATEGORY_PHRASES"]

#: Road users: (phrase pattern, categories). Longer phrases first; plural forms included.
CATEGORY_PHRASES: tuple[tuple[str, tuple[str, ...]], ...] = (
    (r"(?:the )?ego(?: vehicle| car)?|(?:the )?self[- ]driving (?:car|vehicle)", ("EGO_VEHICLE",)),
    (r"our (?:car|vehicle)", ("EGO_VEHICLE",)),
    (
        r"(?:the )?(?:av|autonomous (?:car|vehicle)|test vehicle|host (?:car|vehicle)|vehicle under test"
        r"|(?:subject|instrumented|probe|experimental|data[- ]collection|recording) (?:car|vehicle))",
        ("EGO_VEHICLE",),
    ),
    (r"vulnerable road users?|vrus?", ("VULNERABLE_ROAD_USER",)),
    (
        r"people riding (?:bicycles|bikes)|bicycle riders?|bike riders?"
        r"|(?:someone|somebody|persons?|people|kids?|children|child) (?:on|riding)"
        r" (?:a |their )?(?:bikes?|bicycles?)",
        ("BICYCLIST",),
    ),
    (r"people riding motorcycles|motorcycle riders?|motorcyclists?", ("MOTORCYCLIST",)),
    (
        r"scooter riders?|wheeled riders?|(?:someone|somebody|a person|people|persons) (?:on|riding)"
        r" (?:an? )?(?:e-|electric )?(?:scooters?|skateboards?)"
        r"(?: or (?:an? )?(?:e-|electric )?(?:scooters?|skateboards?))?",
        ("WHEELED_RIDER",),
    ),
    (r"(?:bi)?cyclists?|(?:pedal )?(?:bi)?cycles?|bikes?", ("BICYCLE", "BICYCLIST")),
    (r"motorcycles?|motorbikes?", ("MOTORCYCLE",)),
    # before "pedestrians" and "signs"
    (
        r"mobile (?:pedestrian )?(?:crossing )?signs?|(?:portable|mobile) crosswalk signs?",
        ("MOBILE_PEDESTRIAN_CROSSING_SIGN",),
    ),
    (r"school bus(?:es)?", ("SCHOOL_BUS",)),
    (r"articulated lorr(?:y|ies)", ("TRUCK",)),
    (r"articulated bus(?:es)?|bendy bus(?:es)?", ("ARTICULATED_BUS",)),
    (r"city bus(?:es)?", ("BUS",)),
    (r"bus(?:es)?|coach(?:es)?", ("BUS", "ARTICULATED_BUS", "SCHOOL_BUS")),
    (r"box trucks?|box vans?|delivery trucks?|delivery vans?", ("BOX_TRUCK",)),
    (r"truck cabs?|semi[- ]trucks?|tractor units?|tractor cabs?", ("TRUCK_CAB",)),
    # "trucks" is AV2's TRUCK (box trucks and truck cabs are categories of their own; nine of ten
    # independent reference writers read it so); "trucks of any kind" is all three
    (
        r"trucks? of (?:any|every|all) (?:kinds?|types?|sorts?)"
        r"|(?:any|every|all) (?:kinds?|types?|sorts?) of trucks?",
        ("TRUCK", "BOX_TRUCK", "TRUCK_CAB"),
    ),
    (r"hgvs?|heavy goods vehicles?", ("TRUCK", "BOX_TRUCK", "TRUCK_CAB")),
    (r"trucks?|lorr(?:y|ies)", ("TRUCK",)),
    (r"(?:large|big|heavy) (?:vehicles?|vehs?)", ("LARGE_VEHICLE",)),
    (
        r"(?:(?:variable )?message|electronic|lighted|led) (?:board|sign) trailers?|message boards?"
        r"|message signs?",
        ("MESSAGE_BOARD_TRAILER",),
    ),
    (
        r"(?:portable |temporary )?traffic lights? trailers?|portable traffic lights?",
        ("TRAFFIC_LIGHT_TRAILER",),
    ),
    (r"(?:vehicular )?trailers?", ("VEHICULAR_TRAILER",)),
    (r"trams?|streetcars?|trains?|trolleys?|railed vehicles?", ("RAILED_VEHICLE",)),
    (
        r"(?:regular |normal |ordinary )?cars?|sedans?|suvs?|vans?|pickups?|passenger (?:vehicles?|cars?)"
        r"|regular vehicles?",
        ("REGULAR_VEHICLE",),
    ),
    (r"(?:police officers?|traffic officers?|flaggers?|official signall?ers?)", ("OFFICIAL_SIGNALER",)),
    (r"(?:motor )?vehicles?|vehs?", ("VEHICLE",)),
    (r"(?:electric |e-)?scooters?|wheeled devices?|skateboards?", ("WHEELED_DEVICE",)),
    (
        r"(?:people|persons?|pedestrians?) in (?:a )?wheelchairs?|wheelchair users?|wheelchairs?",
        ("WHEELCHAIR",),
    ),
    (r"strollers?|prams?|pushchairs?", ("STROLLER",)),
    (
        r"pedestrians?|people|persons?|someone|somebody|peds?|walkers?|joggers?|passers?-by|passerby"
        r"|children|child|kids?|m[ae]n|wom[ae]n|lad(?:y|ies)|guys?|boys?|girls?|teenagers?|runners?",
        ("PEDESTRIAN",),
    ),
    (r"dogs?", ("DOG",)),
    (r"animals?", ("ANIMAL", "DOG")),
    (r"bollards?", ("BOLLARD",)),
    (r"(?:traffic |construction )?cones?", ("CONSTRUCTION_CONE",)),
    (r"(?:construction )?barrels?", ("CONSTRUCTION_BARREL",)),
    (r"stop signs?", ("STOP_SIGN",)),
    (r"(?:traffic |road |street )?signs?", ("SIGN",)),
    (r"objects?|things?|anything|something|everything|road users?|actors?|agents?", ("ANY",)),
    # last: "traffic" begins other road users' names ("traffic cone", "traffic officer")
    (r"traffic", ("VEHICLE",)),
)
