"""The console's keys, in one table (the footer shows them, grouped, the robot's and the view's on
lines of their own).

Driving is hold-to-drive on the runtime's ``manual`` source: terminals send no key-up, so every
press and every auto-repeat of a held key sends one twist, and letting go sends nothing; the
twist_mux times the source out 0.5 s later. Arrows: up / down forward and back, left / right
strafe (the mecanum base); q / e turn left / right.

The drive keys and the e-stop are priority bindings: they work on every screen, the clear-map
question included. ``space`` only ever engages the soft e-stop, however often it is pressed (a
panicked double tap must not un-stop the robot); releasing is a different, deliberate key,
``u``, and releasing restarts nothing: ``r`` resumes (ISO 13850: the reset is a separate act).

The view keys change only what the console shows, never the robot: ``+`` / ``-`` zoom the map
(``=`` zooms in too, unshifted), ``h j k l`` pan it (west, south, north, east: vi's keys, since
the arrows drive), ``t`` follows the robot (``f`` is the front camera), ``0`` fits the map
again, ``a`` shows only the pots with anomalies in the pot table, ``[`` / ``]`` select the
previous / next pot in it, and ``i`` opens the selected pot's timeline (the patrol history).

A fleet console (``lupin console --as NAME``, spec/fleet.md "The console") has one more line:
``1``..``9`` pick the robot the panels show, ``E`` engages every robot's soft stop (``space``
stops the robot shown; releasing is still ``u``, robot by robot), so the arm presets move to
``F1``..``F6``.
"""
from __future__ import annotations

from textual.binding import Binding

from arm.presets import PRESETS

SPEED = 0.2
"""m/s, forward and strafe."""
TURN = 0.5
"""rad/s."""
DRIVE: dict[str, tuple[float, float, float]] = {
    "up": (SPEED, 0.0, 0.0), "down": (-SPEED, 0.0, 0.0),
    "left": (0.0, SPEED, 0.0), "right": (0.0, -SPEED, 0.0),  # +y is left (REP-103)
    "q": (0.0, 0.0, TURN), "e": (0.0, 0.0, -TURN),
}
"""Key -> (vx, vy, wz) on the manual source."""
ARM_PRESETS: list[str] = list(PRESETS)[:6]
"""Keys 1..6, in ``arm.presets.PRESETS`` order."""
CAMERAS = {"f": "front", "w": "wrist"}
PAN: dict[str, tuple[int, int]] = {"h": (-1, 0), "j": (0, -1), "k": (0, 1), "l": (1, 0)}
"""Key -> map pan direction (east, north), in quarters of the window."""

_drive = Binding.Group("drive", compact=True)
_strafe = Binding.Group("strafe", compact=True)
_turn = Binding.Group("turn")
_arm = Binding.Group("arm", compact=True)
_gripper = Binding.Group("gripper")
_camera = Binding.Group("camera")
_zoom = Binding.Group("zoom", compact=True)
_pan = Binding.Group("pan", compact=True)
_select = Binding.Group("select pot", compact=True)

ROBOT_KEYS: list[Binding] = [
    Binding("up", "drive('up')", "forward", priority=True, group=_drive),
    Binding("down", "drive('down')", "back", priority=True, group=_drive),
    Binding("left", "drive('left')", "strafe left", priority=True, group=_strafe),
    Binding("right", "drive('right')", "strafe right", priority=True, group=_strafe),
    Binding("q", "drive('q')", "turn left", priority=True, group=_turn),
    Binding("e", "drive('e')", "turn right", priority=True, group=_turn),
    Binding("space", "estop(True)", "E-STOP", priority=True),
    Binding("u", "estop(False)", "release e-stop"),
    Binding("r", "send('resume')", "resume"),
    Binding("m", "send('mission_start')", "mission"),
    Binding("p", "send('pause')", "pause"),
    Binding("c", "clear_map", "clear map"),
    *[Binding(str(i + 1), f"preset('{name}')", f"arm to {name}", group=_arm) for i, name in enumerate(ARM_PRESETS)],
    Binding("o", "gripper('open')", "open gripper", group=_gripper),
    Binding("g", "gripper('close')", "close gripper", group=_gripper),
    *[Binding(key, f"snapshot('{camera}')", f"{camera} camera", group=_camera) for key, camera in CAMERAS.items()],
    Binding("ctrl+q", "quit", "quit"),
]
"""What the robot does (and quitting)."""
VIEW_KEYS: list[Binding] = [
    Binding("plus,equals_sign", "zoom(1)", "zoom in", key_display="+", group=_zoom),
    Binding("minus", "zoom(-1)", "zoom out", key_display="-", group=_zoom),
    *[Binding(key, f"pan({dx}, {dy})", f"pan {key}", group=_pan) for key, (dx, dy) in PAN.items()],
    Binding("t", "follow", "follow robot"),
    Binding("0", "fit", "fit map"),
    Binding("a", "anomalies", "pots with anomalies"),
    Binding("left_square_bracket", "select_pot(-1)", "previous pot", key_display="[", group=_select),
    Binding("right_square_bracket", "select_pot(1)", "next pot", key_display="]", group=_select),
    Binding("i", "timeline", "pot timeline"),
]
"""What the console shows (the map's window, the pot table's filter)."""
BINDINGS: list[Binding] = ROBOT_KEYS + VIEW_KEYS
KEY_SECTIONS = [ROBOT_KEYS, VIEW_KEYS]
"""The footer's lines."""

_robot = Binding.Group("robot", compact=True)
FLEET_KEYS: list[Binding] = [
    *[Binding(str(i), f"robot({i - 1})", f"robot {i}", group=_robot) for i in range(1, 10)],
    Binding("E", "stop_fleet", "FLEET E-STOP", priority=True),
]
"""A fleet console's own keys: which robot is shown, and the whole fleet's stop."""
_fleet_arm = Binding.Group("arm")  # not compact: "f1 f2 ..." reads as keys, "f1f2..." would not
FLEET_ROBOT_KEYS: list[Binding] = [
    b for b in ROBOT_KEYS if b.group is not _arm] + [
    Binding(f"f{i + 1}", f"preset('{name}')", f"arm to {name}", group=_fleet_arm) for i, name in enumerate(ARM_PRESETS)]
FLEET_BINDINGS: list[Binding] = FLEET_ROBOT_KEYS + VIEW_KEYS + FLEET_KEYS
FLEET_KEY_SECTIONS = [FLEET_ROBOT_KEYS, VIEW_KEYS, FLEET_KEYS]
