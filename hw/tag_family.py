"""The AprilTag family the pot plates are printed in, and the id type world and mission files use.

The plates are 36h11 (reference/upstream.md): 587 codes, ids 0..586. The original robot
whitelisted 0..21, but any id of the family can be printed on a plate, so a file may name any.
"""
from __future__ import annotations

from typing import Annotated

from pydantic import AfterValidator

TAG_IDS = range(0, 587)
"""Every id of AprilTag 36h11."""


def _in_family(tag: int) -> int:
    if tag not in TAG_IDS:
        raise ValueError(f"must be an AprilTag 36h11 id, 0..{TAG_IDS[-1]} (got {tag})")
    return tag


TagId = Annotated[int, AfterValidator(_in_family)]
"""A tag id field of a world or mission file: any id of the 36h11 family."""
