"""A navigation goal's states (``nav.navigator``): a module of their own so that the navigator's
mixins (``nav.waits``, ``nav.recovery``) and its callers share them without importing it."""
from __future__ import annotations

from enum import Enum


class State(str, Enum):
    IDLE = "idle"
    FOLLOWING = "following"
    RECOVERING = "recovering"
    SUCCEEDED = "succeeded"
    FAILED = "failed"
    CANCELED = "canceled"


TERMINAL = (State.SUCCEEDED, State.FAILED, State.CANCELED)
