"""A patrol recorded to an MCAP file: the Foxglove channels (``mission.record.channels``) into
``foxglove.open_mcap`` on their private context.

``record_patrol(run, path)`` opens the file, starts the channels on the run's scheduler and
wraps ``run.close`` so the file is finished when the run is (``run_to_end`` closes the run in a
``finally``): one last sample of everything (the final map, the pots' colours, the outcome),
then the MCAP summary is written, then the run closes as before. It returns the closer too,
for callers that end a run another way; closing twice is harmless.

Zstd chunks compressed in the logging thread (``compression_threads=0``): the machine has two
cores, the sim and the SLAM worker already use them, and a 1 MB chunk compresses in
milliseconds once every few seconds of robot time.
"""
from __future__ import annotations

from pathlib import Path

import foxglove
from foxglove.mcap import MCAPCompression, MCAPWriteOptions

from hw.errors import InputError
from mission.record.channels import Parts, PatrolChannels

PROFILE = ""
"""MCAP header profile: none of the ROS ones apply (foxglove schemas, protobuf and JSON)."""


class McapRecording:
    """An open MCAP file fed by a run's channels; ``close()`` finishes it (idempotent)."""

    def __init__(self, parts: Parts, path: Path, channels: PatrolChannels | None = None):
        self.path = Path(path)
        self.channels = channels or PatrolChannels.of(parts)
        self._own = channels is None
        """Shared channels (a live server's) are their owner's to stop; ours end with the file."""
        options = MCAPWriteOptions(compression=MCAPCompression.Zstd, compression_threads=0, profile=PROFILE)
        try:
            self.writer = foxglove.open_mcap(self.path, allow_overwrite=True, context=self.channels.context,
                                             writer_options=options)
        except OSError as exc:
            raise InputError(f"{self.path}: cannot write the recording: {exc.strerror or exc}") from None
        self.writer.write_metadata("lupin", {"robot": parts.robot.config.link.robot})  # whose, in a fleet's files
        self.channels.start()
        self._open = True

    def close(self) -> None:
        if not self._open:
            return
        self._open = False
        try:
            self.channels.flush()
            if self._own:
                self.channels.close()
        finally:
            self.writer.close()


def record_patrol(run, path: Path, channels: PatrolChannels | None = None) -> McapRecording:
    """Record ``run`` (a ``PatrolRun``) to ``path`` from now until it is closed. ``channels``:
    share ones already started (e.g. for a live server) instead of making new ones. A file that
    cannot be written is an ``InputError`` (the run is left to its caller to close)."""
    recording = McapRecording(run, path, channels)
    run_close = run.close

    def close() -> None:
        try:
            recording.close()
        finally:
            run_close()

    run.close = close
    return recording
