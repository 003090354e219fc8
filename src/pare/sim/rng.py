"""One seeded random source per episode, from which every random stream derives."""

from __future__ import annotations

import hashlib
import random


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
