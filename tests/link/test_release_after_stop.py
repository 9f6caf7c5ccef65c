"""A release queued on the link before a stop arrived is refused in its turn, never applied
after the stop (mission.link.server): the stop is applied at once on Zenoh's thread, the release
waits for the runtime's beat, and must not undo the newer stop."""
from __future__ import annotations

import queue

from mission.link.server import LinkServer, _Pending


class Service:
    def __init__(self):
        self.calls: list[bool] = []

    def estop(self, engaged: bool) -> None:
        self.calls.append(engaged)


class Release:
    engaged = False

    def model_dump(self, exclude=()):
        return {"engaged": False}


def server_over(service: Service) -> LinkServer:
    """The server's command path alone (its queue, its stop count, its drain), no Zenoh."""
    server = LinkServer.__new__(LinkServer)
    server.service, server._inbox, server._stopped, server.commands_done = service, queue.SimpleQueue(), 0, 0
    return server


def queue_release(server: LinkServer) -> _Pending:
    pending = _Pending("estop", Release(), stops_before=server._stopped)
    server._inbox.put(pending)
    return pending


def test_a_release_queued_before_a_stop_is_refused_not_applied():
    service = Service()
    server = server_over(service)
    early = queue_release(server)
    server._stop_now()  # arrives while the release waits for the runtime's beat
    server._drain(0.0)
    assert service.calls == [True]  # the stop, and nothing after it
    assert early.done.is_set() and "a stop came after it" in early.error


def test_a_release_after_the_stop_is_applied():
    service = Service()
    server = server_over(service)
    server._stop_now()
    late = queue_release(server)
    server._drain(0.0)
    assert service.calls == [True, False] and late.error is None and late.done.is_set()
