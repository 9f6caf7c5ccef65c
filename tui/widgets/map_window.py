"""Which part of the world the map panel shows: fitted to what is known, or zoomed, panned and
following the robot (the operator's keys, :mod:`tui.keys`).

The default is the fit: the window around everything the view knows (the explored part of the
map, the pots, the robot, the goal), recomputed on every draw, so it keeps fitting while the
SLAM grid grows during a patrol. Zooming stores an absolute scale (pixels per metre) and
freezes the centre where it was, so a zoomed view neither drifts nor changes scale as the map
grows under it; zooming back out to the fit returns to the fit. Panning moves the centre by a
quarter of the window and stops following; following keeps the robot in the centre (starting
from the fit, it first zooms in to about ``FOLLOW_SPAN`` metres across, since a whole
greenhouse centred on the robot is half empty).

Pure and terminal-free: :meth:`MapWindow.frame` turns the state, the fit and the panel's size
in pixels into the world window the canvas draws.
"""
from __future__ import annotations

from dataclasses import dataclass

Bounds = tuple[float, float, float, float]
"""World x0, x1, y0, y1."""

ZOOM_STEP = 1.5
"""Scale factor of one + or - press."""
MAX_SCALE = 40.0
"""Pixels per metre at the most: 2.5 cm a pixel, two pixels to a 0.05 m map cell."""
FOLLOW_SPAN = 12.0
"""Metres across the panel when following starts from the fit (a bay and its neighbours)."""
PAN_FRACTION = 0.25
"""One pan press moves the window by this part of its width (or height)."""


def fit_scale(fit: Bounds, width: int, height: int) -> float:
    """Pixels per metre at which ``fit`` just fills ``width`` x ``height`` pixels."""
    x0, x1, y0, y1 = fit
    return min(width / max(x1 - x0, 1e-6), height / max(y1 - y0, 1e-6))


@dataclass
class Frame:
    """What one draw shows: the world window and how it relates to the fit."""

    bounds: Bounds
    scale: float
    """Pixels per metre."""
    zoom: float
    """``scale`` over the fit's scale (1.0: fitted)."""
    centre: tuple[float, float]


@dataclass
class MapWindow:
    scale: float | None = None
    """Pixels per metre; None: the fit's, whatever it is at each draw."""
    centre: tuple[float, float] | None = None
    """World centre; None: the fit's centre (or the robot while following)."""
    follow: bool = False

    @property
    def fitted(self) -> bool:
        return self.scale is None and self.centre is None and not self.follow

    def frame(self, fit: Bounds, robot: tuple[float, float], width: int, height: int) -> Frame:
        """The window for a panel of ``width`` x ``height`` pixels."""
        base = fit_scale(fit, width, height)
        scale = base if self.scale is None else self.scale
        if self.follow:
            cx, cy = robot
        elif self.centre is not None:
            cx, cy = self.centre
        else:
            cx, cy = (fit[0] + fit[1]) / 2, (fit[2] + fit[3]) / 2
        hw, hh = width / scale / 2, height / scale / 2
        return Frame((cx - hw, cx + hw, cy - hh, cy + hh), scale, scale / base, (cx, cy))

    # --- the operator's keys -----------------------------------------------------------------
    def zoom(self, steps: int, now: Frame) -> None:
        """In (``steps`` > 0) or out by ``ZOOM_STEP`` a step, about the centre shown now; out
        to the fit's scale or past it is the fit again (still following, if following)."""
        base = now.scale / now.zoom
        scale = min(now.scale * ZOOM_STEP ** steps, MAX_SCALE)
        if scale <= base * (1 + 1e-6):
            self.scale = None
            if not self.follow:
                self.centre = None
            return
        self.scale = scale
        if not self.follow:
            self.centre = now.centre

    def pan(self, dx: int, dy: int, now: Frame) -> None:
        """Move the window by a quarter of its size (x east, y north); stops following."""
        x0, x1, y0, y1 = now.bounds
        cx, cy = now.centre
        self.centre = (cx + dx * PAN_FRACTION * (x1 - x0), cy + dy * PAN_FRACTION * (y1 - y0))
        self.follow = False

    def toggle_follow(self, now: Frame, width: int) -> None:
        """Follow the robot (zooming in to ``FOLLOW_SPAN`` across from the fit), or stop
        following and keep the window where the robot was."""
        if self.follow:
            self.follow, self.centre = False, now.centre
            return
        self.follow, self.centre = True, None
        if self.scale is None:
            wanted = min(width / FOLLOW_SPAN, MAX_SCALE)
            self.scale = wanted if wanted > now.scale / now.zoom * (1 + 1e-6) else None

    def fit(self) -> None:
        """Back to the default: fitted to what is known, not following."""
        self.scale, self.centre, self.follow = None, None, False
