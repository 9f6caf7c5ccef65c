"""People on the console's map: a disc where each tracked person is (violet for someone the rules
act on, dim for a track they do not), a tick to where a walker will be in a second, none for
someone standing; and the panel draws again when only the people moved."""
from __future__ import annotations

import asyncio

import numpy as np

from mission.link.view import GridView, PersonView, RobotView
from tests.tui.fakes import Recorder
from tests.tui.test_map import colour
from tui.app import make_app
from tui.widgets.map_panel import FREE, PERSON, STRIDE, TRACK, map_pixels


def room(*people: PersonView) -> RobotView:
    """A 4 x 2 m free room (0.05 m cells), the robot at its left."""
    return RobotView(pose=(0.3, 1.0, 0.0), grid=GridView(np.zeros((40, 80), np.int8), 0.05, 0.0, 0.0),
                     people=list(people))


WALKER = PersonView(3, 2.0, 1.0, vx=0.0, vy=-0.6, radius=0.25, confidence=0.9, walked=True)
"""Walking south at 0.6 m/s across the middle of the room."""
STANDING = PersonView(5, 3.5, 1.5, radius=0.2, confidence=0.6)


def test_people_are_discs_where_they_are_with_a_tick_along_their_walk():
    cv = map_pixels(room(WALKER, STANDING), 80, 20)  # 20 pixels per metre
    assert colour(cv, 2.0 + 0.15, 1.0) == PERSON and colour(cv, 2.0 - 0.15, 1.0 + 0.1) == PERSON  # the body
    assert colour(cv, 2.0, 1.0 - 0.45) == STRIDE  # past the body, on the way south
    assert colour(cv, 2.0, 1.0 + 0.45) == FREE  # nothing behind them
    assert colour(cv, 2.0 + 0.4, 1.0) == FREE  # the disc is their radius, no wider
    assert colour(cv, 3.5, 1.5) == TRACK and colour(cv, 3.5 + 0.1, 1.5) == TRACK  # not acted on: dim
    assert colour(cv, 3.5, 1.5 - 0.3) == FREE  # standing: no tick


def test_a_person_stays_visible_however_far_out_the_map_is_zoomed():
    far = RobotView(pose=(0.0, 0.0, 0.0), grid=GridView(np.zeros((400, 800), np.int8), 0.05, 0.0, 0.0),
                    people=[PersonView(1, 20.0, 10.0, radius=0.2, walked=True)])
    cv = map_pixels(far, 40, 10)  # a 40 m greenhouse in 40 columns: a person is a fraction of a pixel
    c, r = cv.to_pixel(20.0, 10.0)
    block = cv.rgb[int(r) - 1:int(r) + 2, int(c) - 1:int(c) + 2]
    assert np.all(block == PERSON)  # a 3 x 3 blot


def test_the_panel_redraws_when_only_the_people_moved():
    async def run():
        state = {"view": room(WALKER)}
        app = make_app(lambda: state["view"], Recorder())
        async with app.run_test(size=(160, 48)) as pilot:
            await pilot.pause()
            panel = app.query_one("MapPanel")
            before = panel.renders
            panel.show(state["view"])
            assert panel.renders == before  # nothing changed: not drawn again
            moved = room(PersonView(3, 2.0, 0.4, vx=0.0, vy=-0.6, radius=0.25, confidence=0.9, walked=True))
            state["view"] = moved
            panel.show(moved)
            assert panel.renders == before + 1
            drawn = {tuple(c.triplet) for row in panel._strips for seg in row
                     for c in (seg.style.color, seg.style.bgcolor) if c is not None}
            assert PERSON in drawn and STRIDE in drawn  # on the panel's own rows

    asyncio.run(run())
