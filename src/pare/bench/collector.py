"""How a benchmark run uses Python's cyclic garbage collector.

A run's objects are of two kinds: what lives as long as the run (the modules, the scenario library, its
blueprints, the plans) and what one episode makes and drops. Episodes' worlds hold no
reference cycles (apps reach their siblings weakly, triggers hold only the log), so reference counting
frees them as soon as an episode ends; the cyclic collector has little to find, yet each of its full
collections walks every long-lived object again: full collections while the library loads, one before
freezing, and the interpreter's last one at exit (a profile of a whole-library run shows
what they cost).

So a run does what follows. While it starts (loading the library and planning, which make only
long-lived objects) the collector is paused; before the episodes it moves everything alive into the
permanent generation (:func:`gc.freeze`) without a collection first, since at that point almost nothing
is garbage, so a collection would walk the whole heap to free nearly nothing; while the
episodes play it runs as usual over the episodes' own objects. Both are undone when the run ends, so a
caller's process (a notebook, a test session) gets its collector back as it was.
"""

from __future__ import annotations

import gc
from collections.abc import Iterator
from contextlib import contextmanager


@contextmanager
def paused() -> Iterator[None]:
    """No automatic collection inside the block (for work that makes only long-lived objects); the
    collector is enabled again afterwards if it was before.
    """
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_enabled:
            gc.enable()


@contextmanager
def long_lived_frozen() -> Iterator[None]:
    """Everything alive now is left out of the collector's work inside the block, and the collector
    runs (as it was before, once the block ends) over what the block makes.
    """
    was_enabled = gc.isenabled()
    gc.freeze()
    gc.enable()
    try:
        yield
    finally:
        gc.unfreeze()  # the caller's own objects frozen with the run's are collectable again
        if not was_enabled:
            gc.disable()


def settle() -> None:
    """Collect what the work just done left behind, then freeze what survives: for a process that does
    many pieces of work one after another (the gate self-tests scenario after scenario, each leaving
    caches and blueprints behind). Each collection then walks only what was made since the last piece
    instead of everything the process holds: on the gate in one process, full collections had taken a
    quarter of its time. Inside :func:`long_lived_frozen`, its end makes all of it collectable again.
    """
    gc.collect()
    gc.freeze()


def skip_final_collection() -> None:
    """Leave every object alive now out of the interpreter's last collection, for a process about to end.

    At exit the interpreter collects cycles one last time, walking every object still alive (the whole
    library after a run: about a tenth of ``pare run`` on the library); the memory goes back to the
    operating system anyway. Only cycles still alive at exit are then left without finalizers running,
    and PARE closes its files and processes explicitly rather than leaving that to the collector.
    """
    gc.freeze()
