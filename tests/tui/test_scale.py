"""The console at greenhouse scale under Pilot (issue 19): a 200-pot patrol in two bays. The
map fits what is known, zooms, pans and follows the robot, and keeps fitting as the map grows;
the pot table follows the pot in progress and filters to the pots with anomalies; the mission
tree shows the running branch, also while the patrol is held. The view keys send nothing."""
from __future__ import annotations

import pytest

from tests.tui.fakes import console, greenhouse_grid, greenhouse_view, has_anomaly, patrol_tree
from tui.widgets.map_panel import HEADING, ROBOT
from tui.widgets.map_window import ZOOM_STEP


def frame(app):
    return app.main.map_panel.frame


def test_the_map_fits_zooms_pans_and_follows():
    v = greenhouse_view()
    seen = []

    def look(app):
        f, panel = frame(app), app.main.map_panel
        seen.append((f.zoom, f.centre, f.bounds, str(panel.border_title), v.pose[:2]))

    def drive(app):
        v.pose = (v.pose[0] + 2.0, v.pose[1] + 1.0, 0.5)
        app.redraw()

    rec, app = console(lambda: v, [look, "plus", look, "equals_sign", look, "minus", look, "l", look, "k", look,
                                   "t", look, drive, look, "t", drive, look, "0", look])
    assert rec.sent == []  # what the console shows is not the robot's business
    fit, z1, z2, z3, east, north, follow, followed, let_go, refit = seen
    # fitted: the greenhouse (x -1 .. 31, y -1 .. 11 and a margin), not the 55 m grid it lies in
    assert fit[0] == 1.0 and fit[3] == "map · fitted"
    x0, x1, y0, y1 = fit[2]
    assert x0 <= -1.5 and x1 >= 31.5 and y0 <= -1.5 and y1 >= 11.5
    assert min(x1 - x0, (y1 - y0) * 94 / 58) < 40  # the grid is 55 m across
    assert z1[0] == pytest.approx(ZOOM_STEP) and z2[0] == pytest.approx(ZOOM_STEP ** 2) and z3[0] == pytest.approx(ZOOM_STEP)
    assert z1[1] == pytest.approx(fit[1]) and "zoom 1.5x" in z1[3]  # about the centre shown
    width = z3[2][1] - z3[2][0]
    assert east[1] == pytest.approx((z3[1][0] + width / 4, z3[1][1])) and "panned" in east[3]
    assert north[1][1] > east[1][1]
    assert follow[1] == pytest.approx(follow[4]) and followed[1] == pytest.approx(followed[4])  # centred as it drives
    assert followed[4] != follow[4] and "following the robot" in followed[3]
    assert let_go[1] == pytest.approx(followed[4]) and let_go[4] != followed[4]  # t again: stays as the robot drives on
    assert refit[0] == 1.0 and refit[3] == "map · fitted"


def test_the_robot_is_drawn_in_the_middle_of_the_panel_while_followed():
    v = greenhouse_view()
    at = {}

    def look(app):
        panel = app.main.map_panel
        w, h = panel.content_size.width, panel.content_size.height
        col, segments = 0, panel.render_line(h // 2)
        for seg in segments:  # the character in the middle of the panel: its two pixels
            if col <= w // 2 < col + len(seg.text):
                at["colours"] = {tuple(seg.style.color.triplet), tuple(seg.style.bgcolor.triplet)}
                break
            col += len(seg.text)

    console(lambda: v, ["t", look])
    assert at["colours"] & {ROBOT, HEADING}


def test_the_fit_keeps_up_with_a_growing_map():
    v = greenhouse_view()
    v.pots = v.pots[:100]  # bay 1's pots: only the map reaches into bay 2
    v.grid = greenhouse_grid(east=14.0)
    seen = []

    def grow(app):
        seen.append(frame(app).bounds)
        v.grid = greenhouse_grid(east=31.0)  # the link hands over a bigger grid, as SLAM grows it
        app.redraw()

    console(lambda: v, [grow, lambda app: seen.append(frame(app).bounds)])
    before, after = seen
    assert before[1] < 20.0 and after[1] >= 31.5 and after[0] <= -1.5


def test_the_pot_table_follows_the_pot_in_progress():
    v = greenhouse_view(done=120)
    seen = []

    def look(app):
        table = app.main.pots_table
        seen.append((table.row_count, table.visible_rows()))

    def next_pots(app):
        for p in v.pots[120:170]:
            p.status = "inspected"
        v.pots[170].status = "active"
        app.redraw()

    rec, app = console(lambda: v, [look, next_pots, look])
    (rows, first), (_, second) = seen
    assert rows == 200
    assert 120 in first and 0 not in first  # P121 in view, the top of the table scrolled away
    assert 170 in second and 120 not in second


def test_a_shows_only_the_pots_with_anomalies():
    v = greenhouse_view(done=120)
    flagged = [p.id for p in v.pots if p.anomalies]
    assert flagged == [f"P{i + 1:03d}" for i in range(120) if has_anomaly(i)]
    seen = {}

    def look(name):
        def at(app):
            table = app.main.pots_table
            seen[name] = ([r[0] for r in table.rows], {r[5] for r in table.rows}, str(table.border_title))
        return at

    def new_anomaly(app):
        v.pots[120].status, v.pots[120].anomalies = "failed", ["unreachable"]
        v.pots[121].status = "active"
        app.redraw()

    rec, app = console(lambda: v, [look("all"), "a", look("filtered"), new_anomaly, look("more"), "a", look("back")])
    assert rec.sent == []
    assert len(seen["all"][0]) == 200 and seen["all"][2] == "pots: 200"
    ids, kinds, title = seen["filtered"]
    assert ids == flagged and kinds == {"no_bloom"} and title == f"pots with anomalies: {len(flagged)} of 200"
    assert seen["more"][0] == flagged + ["P121"] and "unreachable" in seen["more"][1]
    assert len(seen["back"][0]) == 200 and seen["back"][2] == "pots: 200"


def running(app) -> int:
    return next(i for i, line in enumerate(app.main.mission_tree.shown) if "(navigate) [*]" in line)


def test_the_tree_shows_the_running_branch():
    v = greenhouse_view(done=120)
    seen = {}

    def look(app):
        tree = app.main.mission_tree
        seen["shown"], seen["line"] = list(tree.shown), running(app)
        seen["in_view"] = tree.in_view(seen["line"])

    console(lambda: v, [look])
    shown = "\n".join(seen["shown"])
    assert len(v.tree.splitlines()) > 2500 and len(seen["shown"]) < 250  # folded: one line a pot, plus the branch
    assert "approach P121 (navigate) [*]" in shown and seen["in_view"]
    assert "battery low [✕]" in shown and "battery low?" not in shown and "go home" not in shown  # the idle branch: one line
    assert "-^- P001 [✓]" in shown and "visit P001" not in shown  # a finished pot: its line only
    assert "-^- P200 [-]" in shown and "visit P200" not in shown


def test_a_held_patrol_keeps_the_pot_in_progress_open_and_in_view():
    v = greenhouse_view(done=120)
    seen = {}

    def pause(app):
        v.tree = patrol_tree([p.status for p in v.pots], held="paused by the operator")
        app.redraw()

    def look(app):
        tree = app.main.mission_tree
        line = next(i for i, s in enumerate(tree.shown) if "approach P121 (navigate) [-]" in s)
        seen["shown"], seen["in_view"] = "\n".join(tree.shown), tree.in_view(line)

    console(lambda: v, [pause, look])
    assert "operator pause [*] -- paused by the operator" in seen["shown"] and seen["in_view"]
    assert "visit P120" not in seen["shown"]


def test_a_tree_that_arrives_after_the_console_opened_is_followed():
    """The link's first tree comes a beat or more after the console starts."""
    v = greenhouse_view(done=150)
    tree, v.tree = v.tree, ""
    seen = {}

    def arrive(app):
        v.tree = tree
        app.redraw()

    def look(app):
        seen["in_view"] = app.main.mission_tree.in_view(running(app))

    console(lambda: v, [arrive, look])
    assert seen["in_view"]
