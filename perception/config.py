"""Configuration of perception: the HSV flower detector, the AprilTag reader, camera rates.

Override in YAML or ``LUPIN_PERCEPTION__...``.
"""
from __future__ import annotations

from hw.config import Strict


class PerceptionConfig(Strict):
    """The wrist-camera flower detector and the front-camera tag reader."""
