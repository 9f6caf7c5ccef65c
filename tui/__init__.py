"""The operator console (Textual): ``tui.app.make_app(view_source, commands)``.

It draws only from a ``mission.link.view.RobotView`` and acts only through a ``Commands``
object, so it runs the same over the Zenoh link, against an in-process runtime, or in a test.

- ``app.py``: the app: polls the view, sends commands and asks the patrol history on worker
  threads, handles the keys;
- ``keys.py``: the key table (teleop speeds, arm presets, cameras; the view's keys: zoom, pan,
  follow, fit, the anomaly filter, picking a pot, its timeline);
- ``messages.py``: what the workers tell the app (a refusal, a snapshot, the history's answers);
- ``history_marks.py``: the pot table's history cells (what changed since the last patrol, the
  pest streak) from the robot's answers;
- ``screens/``: the main screen (the layout), the clear-map question, a pot's timeline;
- ``widgets/``: one module per screen area: status bar, map (and its window: fit, zoom, pan,
  follow), mission tree, pots, camera, log, the footer's keys; and what two of them share:
  ``text_lines`` (a panel of text lines drawn through the line API), ``follow`` (keeping a
  line in view);
- ``halfblocks.py``: pictures as '▀' characters (the map and the camera);
- ``console.tcss``: the stylesheet.
"""
