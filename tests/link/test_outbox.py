"""The outbox never makes the control loop wait: a stuck network fills the queue, the oldest
messages are dropped, posting stays instant, and sending resumes with the newest."""
from __future__ import annotations

import threading

from mission.link.outbox import Outbox


def test_a_stuck_link_drops_the_oldest_and_never_blocks_the_poster():
    release, sent = threading.Event(), []

    def put(key, data):
        release.wait(5)
        sent.append(data)

    box = Outbox(put, size=8)
    try:
        for i in range(100):  # the sender is stuck on the first message
            box.post("k", lambda i=i: b"%d" % i)
        assert box.dropped >= 100 - 8 - 1
        release.set()
        box.close(timeout=5)
    finally:
        release.set()
    assert sent[-1] == b"99" and len(sent) <= 9  # the newest made it; the rest of the backlog was dropped
    assert box.bytes["k"] == sum(len(d) for d in sent)


def test_a_failing_payload_or_put_is_logged_not_raised(caplog):
    def put(key, data):
        if data == b"bad":
            raise OSError("network down")

    box = Outbox(put, size=8)
    box.post("k", lambda: 1 / 0)
    box.post("k", lambda: b"bad")
    box.post("k", lambda: None)  # nothing to send this time
    box.post("k", lambda: b"ok")
    box.close(timeout=5)
    assert box.sent == 1 and box.bytes["k"] == 2
