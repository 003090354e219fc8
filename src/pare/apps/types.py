"""Field types shared by apps."""

from __future__ import annotations

from datetime import datetime
from typing import Annotated

from pydantic import AfterValidator

from pare.sim.clock import ensure_utc

SimTime = Annotated[datetime, AfterValidator(ensure_utc)]
"""A point in simulated time. Accepts ISO 8601 (``2025-03-03T10:00:00``, ``2025-03-03 10:00``);
a time without a zone is taken as the simulation's zone (UTC)."""
