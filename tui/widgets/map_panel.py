"""The map panel: occupancy, inflated-cost shading, the scan, the plan and goal, the pots by
status, the people the robot tracks and the robot with its heading, in half-block characters
(two square pixels each). On a fleet console the other robots are drawn too, each with its plan,
in a colour of its own (``FLEET``): the fleet view.

:func:`render_map` is pure (view in, one ``Strip`` per character row out), so it is measured
and tested without a terminal. The picture is one RGB array built with numpy:

- the window fits what is known (the explored part of the map, the pots, the robot, the goal),
  not the whole costmap, much of it unknown, and keeps fitting as the map grows; the operator
  zooms, pans and follows the robot from there (:mod:`tui.widgets.map_window`);
- each pixel takes the *maximum* of the grid cells it covers (``np.maximum.reduceat`` along
  both axes), so a wall one cell thick or a lone box survives any zoom; in int8 order that is
  occupied > free > unknown, exactly the priority wanted. (Nearest-cell sampling drops most of
  a 0.05 m wall at 0.2 m per pixel.)
- the few overlays are drawn on top as dots, then :mod:`tui.halfblocks` cuts the rows into runs
  of one colour pair. The panel hands Textual those strips through the line API (``Text`` /
  ``Content`` would cost about ten times more per frame), and only when its inputs changed.
"""
from __future__ import annotations

import math

import numpy as np
from rich.text import Text
from textual.strip import Strip
from textual.widget import Widget

from mission.link.view import GridView, RobotView
from nav.grid_geometry import GridGeometry
from nav.occupancy import FREE_MAX, OCCUPIED_MIN
from tui.halfblocks import half_block_rows
from tui.widgets.map_window import Frame, MapWindow

UNKNOWN, FREE, MAYBE, OCCUPIED = (28, 28, 36), (70, 74, 70), (110, 110, 104), (235, 235, 225)
COST = np.array([200, 60, 40], dtype=np.float32)
COST_ALPHA = 0.6
PLAN, GOAL, ROBOT, HEADING, SCAN = (250, 210, 60), (230, 80, 230), (60, 200, 255), (255, 255, 255), (255, 80, 160)
POT_COLOURS = {"pending": (150, 150, 150), "active": (60, 130, 255), "inspected": (40, 210, 80),
               "failed": (230, 40, 40), "skipped": (90, 90, 90)}
ANOMALY = (255, 160, 0)
"""An inspected pot with an anomaly (no bloom, a bug, ...)."""
PERSON, TRACK, STRIDE = (170, 100, 255), (110, 80, 150), (235, 215, 255)
"""A person the rules act on (they have walked), a track they do not act on yet (someone who has
stood since the robot saw them, or a box it cannot tell from one), and the velocity tick: violet,
a colour nothing else on the map uses, and a disc where pots are plus signs."""
STRIDE_S = 1.0
"""The velocity tick is where the person will be in this long, s: a walker's 1 m/s is 1 m, as
long as the robot's heading line is 0.35 m, and standing (under ``STILL``) draws none."""
STILL = 0.1
"""m/s below which a track is drawn without a tick (the tracker's filter never reads exactly 0)."""
FLEET = [(255, 140, 40), (120, 230, 200), (200, 200, 90), (150, 170, 255), (255, 120, 120),
         (180, 255, 120), (230, 160, 230), (140, 200, 140)]
"""The other robots of a fleet, by their place in the fleet's list (the shown one is ``ROBOT``)."""
MARGIN = 0.5
"""Metres around what is drawn."""
ROBOT_HALF, NOSE = 0.15, 0.35
"""Metres: half the drawn footprint, length of the heading line."""

_LUT = np.empty((256, 3), np.uint8)  # int8 cell value (as uint8) -> colour
_LUT[:] = UNKNOWN
_LUT[0:FREE_MAX + 1] = FREE  # map_server's trinary thresholds (nav.occupancy)
_LUT[FREE_MAX + 1:OCCUPIED_MIN] = MAYBE
_LUT[OCCUPIED_MIN:101] = OCCUPIED


def pot_colour(status: str, anomalies) -> tuple[int, int, int]:
    if status == "inspected" and anomalies:
        return ANOMALY
    return POT_COLOURS.get(status, POT_COLOURS["pending"])


def legend() -> Text:
    """What the colours mean (the panel's bottom border)."""
    t = Text()
    for name, rgb in (*POT_COLOURS.items(), ("anomaly", ANOMALY), ("plan", PLAN), ("goal", GOAL), ("robot", ROBOT),
                      ("person", PERSON)):
        t.append("■", f"rgb({rgb[0]},{rgb[1]},{rgb[2]})")
        t.append(f"{name} ")
    t.rstrip()
    return t


def _known_extent(g: GridView) -> tuple[float, float, float, float] | None:
    """World bounds (x0, x1, y0, y1) of the grid's known cells, or None if none is known."""
    known = g.data >= 0
    cols, rows = np.flatnonzero(known.any(axis=0)), np.flatnonzero(known.any(axis=1))
    if not len(cols):
        return None
    return g.geometry.cropped(cols[0], rows[0], cols[-1] + 1, rows[-1] + 1).extent


def _bounds(view: RobotView) -> tuple[float, float, float, float]:
    xs, ys = [view.pose[0]], [view.pose[1]]
    for g in (view.grid, view.costmap):
        extent = _known_extent(g) if g is not None else None
        if extent is not None:
            xs += extent[:2]
            ys += extent[2:]
    xs += [p.x for p in view.pots]
    ys += [p.y for p in view.pots]
    if view.goal is not None:
        xs.append(view.goal[0])
        ys.append(view.goal[1])
    xs += [o.pose[0] for o in view.others]
    ys += [o.pose[1] for o in view.others]
    if len(xs) == 1:  # nothing but the robot: 4 m around it
        xs += [view.pose[0] - 2.0, view.pose[0] + 2.0]
        ys += [view.pose[1] - 2.0, view.pose[1] + 2.0]
    return min(xs) - MARGIN, max(xs) + MARGIN, min(ys) - MARGIN, max(ys) + MARGIN


def _spans(idx: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray, int, int]:
    """For pixels whose edges fall in cells ``idx`` (ascending, along one axis of a grid of
    ``n`` cells): the first cell of each (clipped to the grid), whether it touches the grid,
    and the slice of cells they cover."""
    first, after = idx[:-1], np.maximum(idx[1:], idx[:-1] + 1)  # a pixel smaller than a cell still gets one
    on = (after > 0) & (first < n)
    first = np.clip(first, 0, n - 1)
    lo = int(first[0])
    hi = int(np.clip(after[-1], first[-1] + 1, n))
    return first - lo, on, lo, hi


class Canvas:
    """Square pixels over a world window: a grid whose cells are the pixels (``geometry``),
    drawn north up, so (0, 0) is the top-left pixel. ``frame``: the window (fitted to what is
    known unless the operator's ``window`` says otherwise)."""

    def __init__(self, view: RobotView, width: int, height: int, window: MapWindow | None = None):
        self.w, self.h = width, 2 * height
        self.frame: Frame = (window or MapWindow()).frame(_bounds(view), view.pose[:2], self.w, self.h)
        x0, x1, y0, y1 = self.frame.bounds
        self.scale = min(self.w / (x1 - x0), self.h / (y1 - y0))  # pixels per metre
        size = 1.0 / self.scale
        self.geometry = GridGeometry(size, (x0 + x1 - self.w * size) / 2, (y0 + y1 - self.h * size) / 2, self.w, self.h)
        self.rgb = np.empty((self.h, self.w, 3), np.uint8)
        self.rgb[:] = UNKNOWN

    def to_pixel(self, x, y) -> tuple[np.ndarray, np.ndarray]:
        """(column, row) of world points."""
        c, r = self.geometry.pixel_of(x, y)
        return np.floor(c).astype(np.int64), np.floor(r).astype(np.int64)

    def dots(self, x, y, colour) -> None:
        c, r = self.to_pixel(x, y)
        self.pixels(c, r, colour)

    def pixels(self, c: np.ndarray, r: np.ndarray, colour) -> None:
        """Paint pixels (off-canvas ones are skipped); ``colour`` is one RGB or one per pixel."""
        ok = (c >= 0) & (c < self.w) & (r >= 0) & (r < self.h)
        colour = np.asarray(colour, np.uint8)
        self.rgb[r[ok], c[ok]] = colour[ok] if colour.ndim == 2 else colour

    def line(self, points: np.ndarray, colour) -> None:
        """A polyline through (N, 2) world points, sampled twice per pixel along its length."""
        if len(points) < 2:
            return
        steps = np.hypot(*np.diff(points, axis=0).T)
        along = np.concatenate([[0.0], np.cumsum(steps)])
        n = int(min(max(along[-1] * self.scale * 2, 2), 20000))
        s = np.linspace(0.0, along[-1], n)
        self.dots(np.interp(s, along, points[:, 0]), np.interp(s, along, points[:, 1]), colour)

    def pool(self, grid: GridView) -> tuple[np.ndarray, np.ndarray]:
        """Per pixel: the maximum of the grid cells under it, and whether it lies on the grid."""
        pixels, cells = self.geometry, grid.geometry
        xe, ye = (o + np.arange(n + 1) * pixels.resolution for o, n in (
            (pixels.origin_x, self.w), (pixels.origin_y, self.h)))  # pixel edges, bottom row first
        cols, on_x, c0, c1 = _spans(cells.cell_of(xe, cells.origin_y)[0], cells.width)
        rows, on_y, r0, r1 = _spans(cells.cell_of(cells.origin_x, ye)[1], cells.height)
        cells = np.maximum.reduceat(grid.data[r0:r1, c0:c1], cols, axis=1)
        cells = np.maximum.reduceat(cells, rows, axis=0)[::-1]  # top row first
        return cells, on_y[::-1, None] & on_x[None, :]


def map_pixels(view: RobotView, width: int, height: int, window: MapWindow | None = None) -> Canvas:
    """The map as ``width`` x ``2 * height`` RGB pixels (``Canvas.rgb``), and where they are."""
    cv = Canvas(view, max(width, 4), max(height, 2), window)
    occupied = None
    if view.grid is not None and view.grid.data.size:
        cells, on = cv.pool(view.grid)
        cv.rgb[on] = _LUT[cells[on].view(np.uint8)]
        occupied = on & (cells >= OCCUPIED_MIN)
    if view.costmap is not None and view.costmap.data.size:
        cost, on = cv.pool(view.costmap)
        shade = on & (cost > 0)
        if occupied is not None:
            shade &= ~occupied
        a = np.minimum(cost[shade], 100).astype(np.float32)[:, None] * (COST_ALPHA / 100.0)
        cv.rgb[shade] = (cv.rgb[shade] * (1 - a) + COST * a).astype(np.uint8)
    if len(view.scan):
        cv.dots(view.scan[:, 0], view.scan[:, 1], SCAN)
    cv.line(np.asarray(view.plan, float).reshape(-1, 2), PLAN)
    if view.goal is not None:
        c, r = cv.to_pixel(view.goal[0], view.goal[1])
        cv.pixels(c + np.array([0, -1, 1, -1, 1]), r + np.array([0, -1, 1, 1, -1]), GOAL)  # an x
    if view.pots:
        c, r = cv.to_pixel([p.x for p in view.pots], [p.y for p in view.pots])
        colours = np.array([pot_colour(p.status, p.anomalies) for p in view.pots], np.uint8)
        dc, dr = np.array([[0, -1, 1, 0, 0], [0, 0, 0, -1, 1]])[:, :, None]  # a plus, whatever the zoom
        cv.pixels((c + dc).ravel(), (r + dr).ravel(), np.tile(colours, (5, 1)))
    if view.people:
        _people(cv, view.people)
    for o in view.others:
        colour = FLEET[(view.fleet.index(o.robot) if o.robot in view.fleet else 0) % len(FLEET)]
        cv.line(np.asarray(o.plan, float).reshape(-1, 2), colour)
        _robot(cv, o.pose, colour)
    _robot(cv, view.pose, ROBOT)
    return cv


def _robot(cv: Canvas, pose, colour) -> None:
    """A robot's footprint (at least 3 x 3 pixels) and its heading line."""
    x, y, yaw = pose
    half = max(ROBOT_HALF, 1.0 / cv.scale)  # at least 3 x 3 pixels
    n = max(3, int(math.ceil(4 * half * cv.scale)) + 1)  # two samples per pixel: no gaps when turned
    fwd, left = (a.ravel() for a in np.meshgrid(np.linspace(-half, half, n), np.linspace(-half, half, n)))
    cos, sin = math.cos(yaw), math.sin(yaw)
    cv.dots(x + fwd * cos - left * sin, y + fwd * sin + left * cos, colour)
    nose = np.linspace(0.0, max(NOSE, 2.5 / cv.scale), max(3, int(NOSE * cv.scale * 2)))
    cv.dots(x + nose * cos, y + nose * sin, HEADING)


def _people(cv: Canvas, people) -> None:
    """Each person a disc of their body's radius (at least a 3 x 3 pixel blot, whatever the zoom)
    and, when they walk, a tick to where they will be in ``STRIDE_S``."""
    for p in people:
        px = max(p.radius * cv.scale, 1.5)
        k = int(math.ceil(px))
        dc, dr = (a.ravel() for a in np.meshgrid(np.arange(-k, k + 1), np.arange(-k, k + 1)))
        inside = dc * dc + dr * dr <= px * px + 0.5
        c, r = cv.to_pixel(p.x, p.y)
        cv.pixels(c + dc[inside], r + dr[inside], PERSON if p.walked else TRACK)
        if p.speed >= STILL:
            cv.line(np.array([[p.x, p.y], [p.x + p.vx * STRIDE_S, p.y + p.vy * STRIDE_S]]), STRIDE)


def strips(cv: Canvas) -> list[Strip]:
    """The canvas as one ``Strip`` per character row."""
    return [Strip(row, cv.w) for row in half_block_rows(cv.rgb)]


def render_map(view: RobotView, width: int, height: int, window: MapWindow | None = None) -> list[Strip]:
    """``width`` x ``height`` characters of the map (around everything the view knows, unless
    ``window`` says otherwise)."""
    return strips(map_pixels(view, width, height, window))


def title(window: MapWindow, frame: Frame) -> str:
    """The panel's title: how the window was chosen."""
    parts = ["map"]
    if window.follow:
        parts.append("following the robot")
    if frame.zoom > 1.0 + 1e-6:
        parts.append(f"zoom {frame.zoom:.1f}x")
    if window.centre is not None:
        parts.append("panned")
    if len(parts) == 1:
        parts.append("fitted")
    return " · ".join(parts)


def _inputs(view: RobotView) -> tuple:
    """Everything :func:`render_map` reads except the grids' cells (compared separately)."""
    grids = tuple(None if g is None else (g.data.shape, g.resolution, g.origin_x, g.origin_y)
                  for g in (view.grid, view.costmap))
    pots = tuple((p.x, p.y, p.status, bool(p.anomalies)) for p in view.pots)
    plan, scan = np.asarray(view.plan), np.asarray(view.scan)
    people = tuple((p.x, p.y, p.vx, p.vy, p.radius, p.walked) for p in view.people)
    others = tuple((o.robot, tuple(o.pose), np.asarray(o.plan).tobytes()) for o in view.others)
    return (tuple(view.pose), view.goal, grids, pots, plan.shape, plan.tobytes(), scan.shape, scan.tobytes(), people,
            others)


class MapPanel(Widget):
    """Fitted to the panel unless the operator zoomed, panned or follows the robot (the title
    says which); re-rendered only when the view's map inputs, the window or the size changed
    (the link updates the same view in place, so cells are compared, not objects)."""

    def __init__(self, **kw):
        super().__init__(**kw)
        self._strips: list[Strip] = []
        self._drawn: tuple | None = None
        self._cells: list[np.ndarray | None] = [None, None]
        self._view: RobotView | None = None
        self.window = MapWindow()
        self._title = ""
        self.frame: Frame | None = None
        """The window drawn last."""
        self.renders = 0

    def on_mount(self) -> None:
        self.border_subtitle = legend()

    def _same_cells(self, view: RobotView) -> bool:
        same = True
        for i, g in enumerate((view.grid, view.costmap)):
            held = self._cells[i]
            if g is None:
                same &= held is None
                self._cells[i] = None
            elif held is None or held.shape != g.data.shape or not np.array_equal(held, g.data):
                same = False
                self._cells[i] = g.data.copy()
        return same

    def show(self, view: RobotView) -> None:
        self._view = view
        size = self.content_size
        w = self.window
        key = (size.width, size.height, w.scale, w.centre, w.follow, _inputs(view))
        same_cells = self._same_cells(view)
        if same_cells and key == self._drawn:
            return
        self._drawn = key
        cv = map_pixels(view, size.width, size.height, w)
        self._strips, self.frame = strips(cv), cv.frame
        named = title(w, self.frame)
        if named != self._title:  # setting a border title repaints, even unchanged
            self.border_title = self._title = named
        self.renders += 1
        self.refresh()

    # --- the operator's keys (the app's actions call these) ----------------------------------
    def _now(self) -> Frame:
        if self.frame is None:
            self.show(self._view or RobotView())
        return self.frame

    def zoom(self, steps: int) -> None:
        self.window.zoom(steps, self._now())
        self._redraw()

    def pan(self, dx: int, dy: int) -> None:
        self.window.pan(dx, dy, self._now())
        self._redraw()

    def toggle_follow(self) -> None:
        self.window.toggle_follow(self._now(), max(self.content_size.width, 4))
        self._redraw()

    def fit(self) -> None:
        self.window.fit()
        self._redraw()

    def _redraw(self) -> None:
        self.show(self._view or RobotView())

    def on_resize(self) -> None:
        if self._view is not None:
            self.show(self._view)

    def render_line(self, y: int) -> Strip:
        return self._strips[y] if y < len(self._strips) else Strip.blank(self.content_size.width)
