"""The simulation kernel: clock, events, action log, notifications, randomness, faults and noise."""

from pare.sim.clock import SimClock
from pare.sim.events import (
    AfterEvent,
    AfterStart,
    AtTime,
    EventAction,
    EventScheduler,
    ScheduledEvent,
    Trigger,
    WhenLogged,
)
from pare.sim.faults import ToolFailureInjector
from pare.sim.log import ActionLog, Actor, AssistantMode, LogEntry, ToolKind
from pare.sim.noise import NoiseCorpus, NoiseStream, default_corpus
from pare.sim.notifications import Notification, NotificationCenter, NotificationPolicy
from pare.sim.rng import EpisodeRandom

__all__ = [
    "ActionLog",
    "Actor",
    "AfterEvent",
    "AfterStart",
    "AssistantMode",
    "AtTime",
    "EpisodeRandom",
    "EventAction",
    "EventScheduler",
    "LogEntry",
    "NoiseCorpus",
    "NoiseStream",
    "Notification",
    "NotificationCenter",
    "NotificationPolicy",
    "ScheduledEvent",
    "SimClock",
    "ToolFailureInjector",
    "ToolKind",
    "Trigger",
    "WhenLogged",
    "default_corpus",
]
