"""The console's redraw at greenhouse scale: ``link.redraw_large``.

``link.redraw`` (``lupin/bench/link.py``) times a small patrol's view. This one is the view of a
200-pot patrol in a two-bay greenhouse (35 x 20 m grid at 0.05 m, the known part 30 x 14 m):
200 rows in the pot table, a mission tree of about 1,600 lines as py_trees renders it, the
robot moving every frame and, every fifth frame (the link's 2 Hz beat at the console's 10 Hz
poll), one more pot finished, the next one in progress and the tree re-rendered. Each sample is
one poll (``app.redraw()``) plus Textual's render of the screen, at 160 x 48.
"""
from __future__ import annotations

import numpy as np

from lupin.bench import Sample, benchmark
from lupin.bench.link import timed_redraws
from mission.runtime.config import LupinConfig

POTS = 200
FRAMES = 80


def pot_branch(pid: str, status: str) -> list[str]:
    """One pot's lines of py_trees' unicode tree (the patrol's shape, ``mission.patrol.tree``)."""
    mark = {"inspected": "✓", "active": "*"}.get(status, "-")
    step = (lambda i: "✓" if i < 2 else "*" if i == 2 else "-") if status == "active" else (lambda i: mark)
    lines = [f"-^- {pid} [{mark}]" + (" -- oneshot completed" if status == "inspected" else ""),
             f"    {{o}} visit {pid} [{mark}]", f"        {{-}} inspect {pid} [{mark}]"]
    for i, leaf in enumerate(("approach", "front camera", "find", "moved", "wrist", "record", "stow arm")):
        lines.append(f"            --> {leaf} {pid} [{step(i)}]")
    lines.append(f"        --> {pid} failed [-]")
    return lines


def patrol_tree(statuses: list[str]) -> str:
    head = ["-^- Lupin patrol [*]", "    -^- operator pause [*]", "        [o] mission [*]",
            "            {-} battery low [✕]", "                --> battery low? [✕] -- failure",
            "                --> go home [-]", "            {-} patrol [*]",
            "                -^- start-up (once) [✓] -- oneshot completed", "                /_/ pots and tags [*]",
            "                    {-} pots [*]"]
    body = [" " * 24 + line for i, s in enumerate(statuses) for line in pot_branch(f"P{i + 1:03d}", s)]
    return "\n".join(head + body + ["                    --> watch tags [*] -- running", "                --> finish [-]"])


def large_view():
    from mission.link.view import GridView, PotView, RobotView

    rng = np.random.default_rng(0)
    occ = np.full((400, 700), -1, np.int8)
    occ[60:340, 50:650] = 0
    occ[60:340, 50:650][rng.random((280, 600)) < 0.02] = 100
    cost = np.where(occ < 0, -1, np.where(occ == 100, 100, 0)).astype(np.int8)
    pots = [PotView(f"P{i + 1:03d}", 1.0 + (i % 25) * 1.1, 1.0 + (i // 25) * 1.5,
                    "inspected" if i < 100 else "active" if i == 100 else "pending",
                    anomalies=["no_bloom"] if i < 100 and i % 9 == 0 else []) for i in range(POTS)]
    return RobotView(robot="mirte", connected=True, pose=(5.0, 5.0, 0.0), grid=GridView(occ, 0.05, -2.5, -3.0),
                     costmap=GridView(cost, 0.05, -2.5, -3.0), mission_state="running",
                     plan=np.column_stack([np.linspace(5, 12, 60), np.linspace(5, 6, 60)]), pots=pots,
                     scan=rng.random((250, 2)) * 6.0, tree=patrol_tree([p.status for p in pots]))


@benchmark("link.redraw_large")
def redraw_large(config: LupinConfig) -> Sample:
    view = large_view()

    def step(i: int) -> None:
        view.pose = (5.0 + 0.01 * i, 5.0, 0.1 * i)
        if i % 5 == 0:  # a pot finished every fifth frame: table, map marks and tree change
            k = 100 + i // 5
            view.pots[k].status = "inspected"
            if k % 7 == 0:
                view.pots[k].anomalies = ["no_bloom"]
            view.pots[k + 1].status = "active"
            view.tree = patrol_tree([p.status for p in view.pots])

    times = timed_redraws(view, FRAMES, step)
    ms = float(np.median(times[5:]))
    return Sample(times[5:], {"hz": round(1000.0 / ms, 1), "pots": POTS, "tree_lines": view.tree.count("\n") + 1,
                              "terminal": "160x48"})
