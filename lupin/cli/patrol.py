"""`lupin patrol`: the product's main job (spec/cli.md), a scripted patrol to its end.

With no options it patrols every pot of the built-in greenhouse in the sim, as fast as the
machine allows, and writes ``./lupin-report/``. Every input is checked before the robot moves
(world, mission, report path, options: exit 2 with the file, entry and field named).
On a terminal a one-line progress display (pot k of n, the current step, sim and wall time);
quiet when stdout is not a TTY. Ctrl-C or SIGTERM aborts: the goal is cancelled and the report
finished ``aborted``. Exit 0 when the outcome is ``completed``, else 1.
"""
from __future__ import annotations

import signal
import sys
import time
from pathlib import Path
from typing import Optional

import typer

from hw.errors import InputError
from lupin.cli.backend import Backend, announce, backend_option, resolve_backend
from lupin.cli.sim import run_config, world_or_default
from mission.runtime.config import with_overrides, with_seed

DEFAULT_REPORT = Path("lupin-report") / "report.json"


def check_report(report: Path) -> None:
    """``report`` names the JSON; its directory (made here) holds everything beside it."""
    if report.suffix.lower() != ".json":
        raise InputError(f"--report {report}: must name a .json file (images, map and picture go beside it)")
    if report.exists() and report.is_dir():
        raise InputError(f"--report {report}: is a directory")
    try:
        report.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"--report {report}: cannot create {report.parent}: {exc.strerror}") from None


def open_patrol_history(config, history: Optional[str]):
    """The history the patrol is recorded in (``--history``, else ``history.url``), with its spool
    (``history.spool`` in the state directory of ``runtime.backend``: the robot's fixed one or
    ``runtime.state_dir``; else, in the sim, in memory). A server that does not answer is no
    error: the robot runs and its rows wait in the spool (spec/history.md); a malformed URL or
    an unusable local file is exit 2."""
    from mission.history.spool import runtime_spool
    from mission.history.store import open_history
    from mission.history.url import parse_history_url

    url, option = (history, "--history") if history is not None else (config.history.url, "history.url")
    if parse_history_url(url, option) is None:
        return None
    spool = runtime_spool(config.runtime, config.runtime.backend)
    return open_history(url, option, connect_timeout=config.history.connect_timeout, spool=spool)


def surveyed_patrol(config, backend: Backend, world: Optional[Path], events: Optional[Path], report: Path,
                    history: Optional[str] = None):
    """Survey first, then patrol what the survey found on the same running robot (its map and
    SLAM carry on); the survey's mission, map, report and picture go to ``survey/`` beside the report."""
    from mission.jobs.survey import run_to_end, start_hw_survey, write_survey

    check_report(report)
    store = open_patrol_history(config, history)
    out = report.parent / "survey"
    out.mkdir(parents=True, exist_ok=True)
    if backend is Backend.hw:
        if world is not None or events is not None:
            raise InputError("lupin patrol --backend hw --survey: --world and --events are for the sim")
        announce("patrol", backend)
        survey_run, sim_run, name = start_hw_survey(config), None, "greenhouse-survey"
    else:
        from mission.jobs.sim_survey import start_sim_survey
        from mission.patrol.events_file import load_events

        w = world_or_default(world)
        script = [] if events is None else load_events(events, config, w)
        announce("patrol", backend, w)
        (survey_run, sim_run), name = start_sim_survey(w, config), f"{w.name}-survey"
    t0 = time.perf_counter()
    try:
        run_to_end(survey_run)
        write_survey(survey_run, out / "mission.yaml", out / "map.yaml", out / "survey.json", name, time.perf_counter() - t0)
        mission = survey_run.mission(name)
        if not mission.pots:
            raise InputError(f"lupin patrol --survey: the survey found no pots (see {out / 'survey.json'})")
    except BaseException:
        survey_run.close()
        raise
    print(f"survey: {len(mission.pots)} pots found, {survey_run.now - survey_run.t0:.0f} s robot time; patrolling them")
    if sim_run is None:
        from mission.jobs.patrol import start_patrol

        return start_patrol(survey_run.robot, survey_run.nav, mission, survey_run.config, config.perception, report,
                            time.perf_counter, survey_run.close, history=store)
    from mission.jobs.sim_patrol import start_sim_patrol

    return start_sim_patrol(w, mission, survey_run.config, report, time.perf_counter, script, sim_run=sim_run,
                            history=store)


def check_map(mission, saved_map: Optional[Path]) -> None:
    """A ``--map`` must load and cover every pot of the mission (exit 2 naming the pots)."""
    if saved_map is None:
        return
    from mission.patrol.map_coverage import uncovered_pots
    from nav.map_io import load_map

    problems = uncovered_pots(mission, load_map(saved_map))
    if problems:
        raise InputError("\n".join(f"--map {saved_map}: does not cover {p}" for p in problems))


def energy_line(energy) -> str:
    """The charge and what the budget expects at the dock after the next pot (issue 31)."""
    if energy.charge is None:
        return ""
    dock = f", {energy.projected:.0%} at dock" if energy.projected is not None else ""
    return f"charge {energy.charge:.0%}{dock}  "


class Progress:
    """A rich status line: pot k of n, current step, sim and wall time."""

    def __init__(self, total: int):
        from rich.console import Console
        from rich.live import Live

        self.total, self.wall0 = total, time.perf_counter()
        self.live = Live(console=Console(), refresh_per_second=8, transient=True)
        self.live.start()

    def __call__(self, run) -> None:
        tree = run.tree
        k = min(tree.pots_done() + 1, self.total)
        self.live.update(f"pot {k} of {self.total}  {tree.current_step():<28.28}  {energy_line(tree.energy)}"
                         f"{run.robot.scheduler.clock.now():6.1f} s sim  {time.perf_counter() - self.wall0:5.1f} s wall"
                         + (f"\nheading home: {tree.energy.why_home}" if tree.energy.why_home else ""))

    def stop(self) -> None:
        self.live.stop()


def patrol(
    ctx: typer.Context,
    world: Optional[Path] = typer.Option(None, "--world", help="World file (default: the built-in greenhouse)."),
    mission: Optional[Path] = typer.Option(None, "--mission", help="Mission file (default: every pot of the world)."),
    events: Optional[Path] = typer.Option(None, "--events", help="Events file (spec/events.md): timed operator actions and faults, sim only."),
    report: Path = typer.Option(DEFAULT_REPORT, "--report", help="Report JSON to write; images, map, config and run.png go beside it."),
    backend: Optional[Backend] = backend_option(),
    realtime: bool = typer.Option(False, "--realtime", help="Run the sim at wall-clock pace instead of as fast as possible."),
    seed: Optional[int] = typer.Option(None, "--seed", help="Sim seed (overrides config)."),
    record: bool = typer.Option(False, "--record", help="Also record the run for Foxglove: run.mcap beside the report."),
    saved_map: Optional[Path] = typer.Option(None, "--map", help="Localise (AMCL) on this saved map (map_server YAML) "
                                             "instead of mapping from the dock; it must cover every pot."),
    survey: bool = typer.Option(False, "--survey", help="Survey the greenhouse first (lupin survey) and patrol the "
                                "mission it finds; what it wrote goes to survey/ beside the report."),
    history: Optional[str] = typer.Option(None, "--history", metavar="URL",
                                          help="Record the patrol in this history (spec/history.md): a SQLite file, "
                                               "postgresql://user@host/db, or none (default: history.url, "
                                               "lupin-history.db here)."),
    resume: Optional[Path] = typer.Option(None, "--resume", metavar="REPORT",
                                          help="Patrol the pots this report left undone (skipped or never reached), "
                                               "with the mission written beside it."),
    max_legs: Optional[int] = typer.Option(None, "--max-legs", min=1,
                                           help="Trips out from the dock, charging between them (default: as many "
                                                "as it takes)."),
    no_charge: bool = typer.Option(False, "--no-charge", help="The dock does not charge: a patrol longer than the "
                                   "battery ends battery_low at the dock, listing what is left."),
) -> None:
    """Run a scripted patrol mission to its end and write the report."""
    from mission.jobs.patrol import run_to_end, start_hw_patrol
    from mission.patrol.mission_file import load_mission, mission_from_world

    config = run_config(ctx) if seed is None else with_seed(run_config(ctx), seed)
    backend = resolve_backend(backend, config)
    if realtime:
        config = with_overrides(config, {"sim": {"realtime": True}})
    if saved_map is not None:
        config = with_overrides(config, {"nav": {"slam": False, "map_file": str(saved_map)}})
    if max_legs is not None or no_charge:
        config = with_overrides(config, {"patrol": {"energy": {"max_legs": max_legs, "charge": not no_charge}}})
    if resume is not None:
        from mission.patrol.mission_resume import resume_mission

        if mission is not None or survey:
            raise InputError("lupin patrol --resume: the report names the mission; give neither --mission nor --survey")
        mission = _write_resumed(resume_mission(resume), report)
    if survey and (mission is not None or saved_map is not None):
        raise InputError("lupin patrol --survey: the survey writes the mission and maps as it goes; "
                         "give neither --mission nor --map")
    if survey:
        run = surveyed_patrol(config, backend, world, events, report, history)
    elif backend is Backend.hw:
        if mission is None or world is not None:
            raise InputError("lupin patrol --backend hw: give --mission (and no --world: the robot patrols its real greenhouse)")
        if events is not None:
            raise InputError("lupin patrol --backend hw: --events scripts faults into the sim; it does not drive the robot")
        m = load_mission(mission)
        check_map(m, saved_map)
        check_report(report)
        announce("patrol", backend)
        store = open_patrol_history(config, history)  # every input checked; only now does anything start
        run = start_hw_patrol(m, config, report, time.perf_counter, store)
    else:  # the sim path: only here is the simulator loaded
        from mission.jobs.sim_patrol import start_sim_patrol
        from mission.patrol.events_file import load_events

        w = world_or_default(world)
        m = mission_from_world(w) if mission is None else load_mission(mission)
        check_map(m, saved_map)
        script = [] if events is None else load_events(events, config, w)
        check_report(report)
        announce("patrol", backend, w)
        store = open_patrol_history(config, history)
        run = start_sim_patrol(w, m, config, report, time.perf_counter, script, history=store)
    m = run.tree.mission
    if record:
        from mission.record.mcap_file import record_patrol

        try:
            record_patrol(run, report.parent / "run.mcap")  # finished when run_to_end closes the run
        except BaseException:
            run.close()
            raise
    progress = Progress(len(m.pots)) if sys.stdout.isatty() else None
    previous = signal.signal(signal.SIGTERM, _interrupt)  # a service stop aborts like Ctrl-C
    try:
        doc = run_to_end(run, progress or (lambda r: None))
    finally:
        signal.signal(signal.SIGTERM, previous)
        if progress is not None:
            progress.stop()
    print(summary(doc, report))
    if doc["outcome"] != "completed":
        raise typer.Exit(1)


def _write_resumed(mission, report: Path) -> Path:
    """The resumed mission as a file (beside the new report) the patrol then loads as usual."""
    from hw.atomic_file import write_atomic
    from mission.patrol.mission_file import dump_mission

    check_report(report)
    path = report.parent / "resumed-mission.yaml"
    write_atomic(path, dump_mission(mission).encode())
    return path


def _interrupt(signum, frame) -> None:
    raise KeyboardInterrupt


def summary(doc: dict, report: Path) -> str:
    """The end-of-patrol lines: the outcome with every pot not inspected counted by why
    (``completed, 84/186 pots inspected, 102 unreachable``), then a line per pot and anomaly."""
    from mission.patrol.report import not_inspected

    pots = doc["pots"]
    done = sum(p["status"] == "inspected" for p in pots)
    short = "".join(f", {n} {kind}" for kind, n in not_inspected(doc).items())
    lines = [f"{doc['mission']}: {doc['outcome']}, {done}/{len(pots)} pots inspected{short}, "
             f"{doc['sim_time_s']:.1f} s robot time, {doc['wall_time_s']:.1f} s wall, {doc['distance_m']:.1f} m driven"]
    for p in pots:
        f = p.get("flower") or {}
        lines.append(f"  {p['id']:<6} {p['status']:<9} tag {p['tag_read']!s:<5} {f.get('color', '-'):<6}"
                     f"{' x' + str(f['blooms']) if f.get('blooms') else ''}")
    for a in doc["anomalies"]:
        lines.append(f"  anomaly {a['kind']} at {a['pot']}: {a['detail']}")
    for t in doc["discovered_tags"]:
        lines.append(f"  discovered tag {t['id']} at ({t['x']:.2f}, {t['y']:.2f})")
    for key, why in doc.get("notes", {}).items():
        lines.append(f"  note {key}: {why}")
    lines += leg_lines(doc.get("legs", []))
    lines += history_lines(doc)
    lines.append(f"report: {report}")
    return "\n".join(lines)


def leg_lines(legs: list[dict]) -> list[str]:
    """A line per leg out from the dock, when the patrol took more than one or came home early."""
    if len(legs) < 2 and not any(g.get("why_home") for g in legs):
        return []

    def at(t, charge) -> str:
        return "-" if t is None else f"{t:.0f} s ({charge:.0%})" if charge is not None else f"{t:.0f} s"

    out = []
    for g in legs:
        line = (f"  leg {g['leg']}: left {at(g['left_s'], g['charge_left'])}, "
                f"back {at(g['returned_s'], g['charge_returned'])}, {g['pots']} pot(s)")
        if g.get("charged_s") is not None:
            line += f", charged by {at(g['charged_s'], g['charge_after'])}"
        out.append(line + (f"; home: {g['why_home']}" if g.get("why_home") else ""))
    return out


def history_lines(doc: dict) -> list[str]:
    """Where the patrol was recorded, and what changed since the previous patrol of its mission."""
    h = doc.get("history")
    if h is None:
        return []
    if h.get("patrol") is None:
        if h.get("spooled"):  # the database did not answer: the patrol waits in the spool (spec/history.md)
            return [f"history: {h['database']} did not answer; the patrol waits in the spool ({h['spooled']} "
                    f"write(s)), sent when it answers (lupin history status|sync)"]
        return [f"history: NOT recorded in {h['database']} (see the errors above)"]
    since = doc.get("changes_since")
    changes = doc.get("changes", [])
    errors = f"; {h['write_errors']} write error(s), see above" if h.get("write_errors") else ""
    errors += f"; {h['spooled']} write(s) wait in the spool" if h.get("spooled") else ""
    head = (f"history: patrol {h['patrol']} in {h['database']}{errors}; " +
            (f"{len(changes)} change(s) since patrol {since['patrol']}" if since else "the mission's first patrol there"))
    return [head] + [f"  change {c['kind']} at {c['pot']}: {c['detail']}" for c in changes]
