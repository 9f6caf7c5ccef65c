"""`lupin detect flower|tag IMAGE... [--json] [--annotate DIR]` (spec/cli.md).

Runs the flower detector or the tag reader on image files (frames saved on the robot, photos)
with the thresholds of the active config, so they can be tuned on real pictures: edit the
config, run again, look at the annotated copies. An unreadable image is one line on stderr and
the command goes on with the others; it then exits 2 (bad input), else 0.

Human output: one line per image, then one indented line per detection. ``--json``: one object
per image per line, ``{"image": ..., "detections": [...]}`` (flower detections: class,
centroid, area, confidence, bug, plus the frame's class, count and bug; tag detections: id,
pose, distance, off-axis angle).
"""
from __future__ import annotations

import json
import math
import sys
from pathlib import Path
from typing import Optional

import cv2
import numpy as np
import typer

from hw.errors import InputError
from lupin.cli.sim import run_config
from perception.annotate import draw_blooms, draw_tags
from perception.detections import FlowerFrame, TagRead
from perception.flower_detector import FlowerDetector
from perception.tag_reader import TagReader

KINDS = ("flower", "tag")


def _read(path: Path):
    """BGR image of ``path``, or None if it cannot be read as an image."""
    if not path.is_file():
        return None
    try:
        data = path.read_bytes()
    except OSError:
        return None
    return cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR) if data else None


def _why(path: Path) -> str:
    if not path.exists():
        return "no such file"
    if path.is_dir():
        return "is a directory"
    return "not a readable image (PNG, JPEG, ...)"


def _flower_text(path: Path, frame: FlowerFrame) -> str:
    head = f"{path}: {frame.flower}" + (f" x{frame.count}" if frame.blooms else "") + (", BUG" if frame.bug else "")
    rows = [f"  {b.cls:<6} at ({b.centroid[0]:.0f}, {b.centroid[1]:.0f})  area {b.area} px  "
            f"confidence {b.confidence:.2f}" + ("  bug" if b.bug else "") for b in frame.blooms]
    rows += [f"  pest on a {p.on} at ({p.centroid[0]:.0f}, {p.centroid[1]:.0f})  area {p.area} px  "
             f"confidence {p.confidence:.2f}" for p in frame.pests]
    return "\n".join([head, *rows])


def _tag_text(path: Path, reads: tuple[TagRead, ...]) -> str:
    head = f"{path}: " + (", ".join(f"tag {r.id}" for r in reads) if reads else "no tag")
    rows = [f"  id {r.id}: x {r.position[0]:+.3f} y {r.position[1]:+.3f} z {r.position[2]:.3f} m, "
            f"distance {r.distance:.3f} m, off-axis {math.degrees(r.off_axis):.1f} deg" for r in reads]
    return "\n".join([head, *rows])


def _annotated_path(directory: Path, path: Path, kind: str, used: set[Path]) -> Path:
    out = directory / f"{path.stem}.{kind}.png"
    k = 1
    while out in used:
        k += 1
        out = directory / f"{path.stem}.{kind}-{k}.png"
    used.add(out)
    return out


def detect(
    ctx: typer.Context,
    kind: str = typer.Argument(..., help="What to detect: flower (wrist frames) or tag (front frames)."),
    images: list[Path] = typer.Argument(..., help="Image files (PNG, JPEG, ...)."),
    as_json: bool = typer.Option(False, "--json", help="One JSON object per image per line."),
    annotate: Optional[Path] = typer.Option(None, "--annotate", help="Write each image with its detections drawn into this directory."),
) -> None:
    """Run the flower detector or the tag reader on image files and print what it found."""
    if kind not in KINDS:
        raise InputError(f"detect: unknown detector {kind!r}; choose flower or tag")
    if annotate is not None and not annotate.is_dir():
        raise InputError(f"--annotate {annotate}: not a directory")
    config = run_config(ctx).perception
    flowers = FlowerDetector(config.flower) if kind == "flower" else None
    tags = TagReader(config.tag) if kind == "tag" else None
    failed, used = 0, set()
    for path in images:
        image = _read(path)
        if image is None:
            print(f"lupin: {path}: {_why(path)}", file=sys.stderr, flush=True)
            failed += 1
            continue
        if flowers is not None:
            frame = flowers(image)
            record = {"image": str(path), **frame.as_dict()}
            text = _flower_text(path, frame)
            drawn = draw_blooms(image, frame) if annotate else None
        else:
            reads = tags(image)
            record = {"image": str(path), "detections": [r.as_dict() for r in reads]}
            text = _tag_text(path, reads)
            drawn = (draw_tags(image, reads, tags.camera_matrix(image.shape[1], image.shape[0]), config.tag.tag_size)
                     if annotate else None)
        print(json.dumps(record) if as_json else text, flush=True)
        if drawn is not None:
            out = _annotated_path(annotate, path, kind, used)
            if not cv2.imwrite(str(out), drawn):
                raise InputError(f"--annotate: could not write {out}")
    if failed:
        raise typer.Exit(2)
