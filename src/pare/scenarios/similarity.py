"""How alike two scenarios are: the same story with the names changed must not enter the library twice.

Three signals, each in [0, 1], combined with fixed weights:

* the story (title and story text) as TF-IDF vectors over the library, compared by cosine, with proper
  names, numbers and common words left out, so that renaming Ann to Joan changes nothing;
* the apps, compared as sets (Jaccard);
* the oracle's tools (what the assistant does, and which events the world sends), compared as sets.
"""

from __future__ import annotations

import math
import re
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass

from pare.scenarios.model import Scenario

WEIGHTS = {"story": 0.6, "apps": 0.15, "tools": 0.25}
THRESHOLD = 0.6
"""Pairs at or above this are too alike: the library stays below it (a test enforces it)."""

_WORD = re.compile(r"[A-Za-z][A-Za-z'-]*")
_STOPWORDS = frozenset(
    [
        "a",
        "about",
        "after",
        "again",
        "all",
        "also",
        "an",
        "and",
        "any",
        "are",
        "as",
        "at",
        "be",
        "because",
        "been",
        "before",
        "but",
        "by",
        "can",
        "could",
        "did",
        "do",
        "does",
        "for",
        "from",
        "had",
        "has",
        "have",
        "he",
        "her",
        "hers",
        "him",
        "his",
        "how",
        "i",
        "if",
        "in",
        "into",
        "is",
        "it",
        "its",
        "just",
        "me",
        "more",
        "most",
        "my",
        "no",
        "not",
        "now",
        "of",
        "on",
        "once",
        "one",
        "only",
        "or",
        "other",
        "our",
        "out",
        "over",
        "own",
        "same",
        "she",
        "should",
        "so",
        "some",
        "than",
        "that",
        "the",
        "their",
        "them",
        "then",
        "there",
        "these",
        "they",
        "this",
        "those",
        "through",
        "to",
        "too",
        "under",
        "until",
        "up",
        "very",
        "was",
        "we",
        "were",
        "what",
        "when",
        "where",
        "which",
        "while",
        "who",
        "why",
        "will",
        "with",
        "would",
        "you",
        "your",
        "yours",
        "assistant",
        "user",
        "must",
        "should",
        "needs",
    ]
)


@dataclass(frozen=True, slots=True)
class Similarity:
    """How alike two scenarios are, overall and by signal."""

    first: str
    second: str
    score: float
    story: float
    apps: float
    tools: float


def story_words(scenario: Scenario) -> list[str]:
    """The story's content words: lower case, without proper names, numbers and common words."""
    return text_words(scenario.title, scenario.story)


def text_words(title: str, story: str) -> list[str]:
    """The content words of a title and a story (see :func:`story_words`)."""
    words = []
    for sentence in re.split(r"(?<=[.!?])\s+", f"{title}. {story}"):
        for index, match in enumerate(_WORD.finditer(sentence)):
            word = match.group(0)
            if index > 0 and word[0].isupper():
                continue  # a name: renaming people and places must not make a story new
            lowered = word.lower().strip("'-")
            if len(lowered) > 2 and lowered not in _STOPWORDS:
                words.append(lowered)
    return words


def _tools(scenario: Scenario) -> set[str]:
    tools = {action.tool for i in scenario.oracle.interventions for action in i.actions}
    tools.update(event.tool for event in scenario.events)
    return tools


def jaccard(left: set[str], right: set[str]) -> float:
    """The share of the two sets' elements they have in common (1 for two empty sets)."""
    union = left | right
    return len(left & right) / len(union) if union else 1.0


def _vectors(scenarios: Sequence[Scenario]) -> list[dict[str, float]]:
    return word_vectors([story_words(scenario) for scenario in scenarios])


def word_vectors(documents_words: Sequence[Sequence[str]]) -> list[dict[str, float]]:
    """TF-IDF vectors (unit length) of word lists, weighted over those lists."""
    counts = [Counter(words) for words in documents_words]
    documents = Counter(word for count in counts for word in count)
    total = len(counts)
    vectors = []
    for count in counts:
        vector = {word: n * (math.log((1 + total) / (1 + documents[word])) + 1) for word, n in count.items()}
        norm = math.sqrt(sum(value * value for value in vector.values())) or 1.0
        vectors.append({word: value / norm for word, value in vector.items()})
    return vectors


def cosine(left: dict[str, float], right: dict[str, float]) -> float:
    """The cosine of two unit-length sparse vectors."""
    if len(left) > len(right):
        left, right = right, left
    return sum(value * right.get(word, 0.0) for word, value in left.items())


def similarities(scenarios: Sequence[Scenario], against: Sequence[Scenario] = ()) -> list[Similarity]:
    """Every pair of ``scenarios``, and each of them with each of ``against`` (a library they would join;
    its pairs among themselves are left out), most alike first. Story words are weighed over all of them.
    """
    everything = [*scenarios, *against]
    vectors = _vectors(everything)
    apps = [set(scenario.all_apps) for scenario in everything]
    tools = [_tools(scenario) for scenario in everything]
    pairs = []
    for i in range(len(scenarios)):
        for j in range(i + 1, len(everything)):
            story = cosine(vectors[i], vectors[j])
            app_share = jaccard(apps[i], apps[j])
            tool_share = jaccard(tools[i], tools[j])
            score = WEIGHTS["story"] * story + WEIGHTS["apps"] * app_share + WEIGHTS["tools"] * tool_share
            pairs.append(Similarity(everything[i].id, everything[j].id, score, story, app_share, tool_share))
    return sorted(pairs, key=lambda pair: (-pair.score, pair.first, pair.second))
