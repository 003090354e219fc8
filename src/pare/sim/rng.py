"""One seeded random source per episode, from which every random stream derives."""

from __future__ import annotations

import hashlib
import random

from pare.errors import SimulationBug


class EpisodeRandom:
    """Named, independent random streams derived from one episode seed.

    Each consumer (tool failures, noise arrivals, noise content, ...) asks for its own stream by name, so
    adding draws to one stream never shifts another: turning noise on does not change which tool calls
    fail. Streams are derived by hashing ``seed`` and the name, which is stable across Python versions and
    processes (unlike ``hash()``).
    """

    __slots__ = ("_streams", "seed")

    def __init__(self, seed: int) -> None:
        self.seed = seed
        self._streams: dict[str, random.Random] = {}

    def stream(self, name: str) -> random.Random:
        """Return the stream called ``name``, creating it on first use."""
        generator = self._streams.get(name)
        if generator is None:
            digest = hashlib.sha256(f"{self.seed}:{name}".encode()).digest()
            generator = random.Random(int.from_bytes(digest[:8], "big"))
            self._streams[name] = generator
        return generator


class _UnusedStream(random.Random):
    """The stream handed to a feature that is off (no tool failures, no noise), which never draws.

    Seeding a stream is the costliest part of setting up a short episode, so features that are off do
    not get one of their own; a draw from this one would be a bug, and says so rather than sharing
    randomness between episodes.
    """

    def random(self) -> float:
        raise SimulationBug("a random draw from the stream of a feature that is off")

    def getrandbits(self, k: int, /) -> int:
        raise SimulationBug("a random draw from the stream of a feature that is off")


UNUSED_STREAM: random.Random = _UnusedStream(0)
"""Shared by every feature that is off; drawing from it raises :class:`~pare.errors.SimulationBug`."""
