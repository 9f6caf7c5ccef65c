"""The fleet's router: zenoh's own router mode, its config written from the fleet's members.

``lupin router`` opens a Zenoh session in ``router`` mode (the pip wheel runs as a router, so no
``zenohd`` is needed; one installed works the same with ``router_config``'s JSON). It listens
on TLS by default, multicast scouting off, and only members whose certificate the fleet's
authority signed connect (mutual TLS). Access control, by certificate common name, is the
table of spec/fleet.md "Security" (default deny; ``flows`` as seen by the router)::

    who         may
    robot R     publish under lupin/R/**, answer queries on lupin/R/cmd/*, lupin/R/stop and
                lupin/fleet/stop, hold the token lupin/R/alive, read lupin/fleet/**
    console     read everything under lupin/**, query any key (commands, stops, history),
                see every robot's token
    dispatcher  read every robot, write lupin/fleet/**, query lupin/*/cmd/** (send patrols)
    everyone    query lupin/*/stop and lupin/fleet/stop: stopping is never refused

Releasing a stop is the command ``lupin/R/cmd/estop`` and commands are consoles' (and the
dispatcher's), so a robot can stop another robot but never release it. A robot cannot declare
a subscriber or a queryable on another robot's commands, so it never reads them.
"""
from __future__ import annotations

import json

import zenoh

from fleet.members import Members
from hw.errors import InputError
from mission.link.session import TlsFiles, session_config
from mission.link.wire import FLEET_STOP, alive_key

DEFAULT_LISTEN = "tls/0.0.0.0:7447"
LIVELINESS = ["liveliness_token", "liveliness_query", "declare_liveliness_subscriber"]


def _rule(rid: str, messages: list[str], flows: list[str], keys: list[str]) -> dict:
    return {"id": rid, "permission": "allow", "messages": messages, "flows": flows, "key_exprs": keys}


def access_control(members: Members) -> dict:
    """zenoh's ``access_control`` section for the fleet (module docstring's table)."""
    rules, subjects, policies = [], [], []
    stops = ["lupin/*/stop", FLEET_STOP]
    for r in members.robots:
        own = f"lupin/{r}"
        rules += [
            _rule(f"{r}.publish", ["put", "delete"], ["ingress"], [f"{own}/**"]),
            _rule(f"{r}.serve", ["declare_queryable"], ["ingress"], [f"{own}/cmd/**", f"{own}/stop", FLEET_STOP]),
            _rule(f"{r}.asked", ["query"], ["egress"], [f"{own}/cmd/**", f"{own}/stop", FLEET_STOP]),
            _rule(f"{r}.answer", ["reply"], ["ingress"], [f"{own}/cmd/**", f"{own}/stop", FLEET_STOP]),
            _rule(f"{r}.alive", ["liveliness_token"], ["ingress"], [alive_key(r)]),
            _rule(f"{r}.fleet", ["declare_subscriber", "put", "delete"], ["ingress", "egress"], ["lupin/fleet/**"]),
        ]
        subjects.append({"id": f"robot {r}", "cert_common_names": [r]})
        policies.append({"rules": [f"{r}.{p}" for p in ("publish", "serve", "asked", "answer", "alive", "fleet")],
                         "subjects": [f"robot {r}"]})
    readers = list(members.consoles) + ([members.dispatcher] if members.dispatcher else [])
    rules += [
        _rule("read", ["declare_subscriber", "put", "delete"], ["ingress", "egress"], ["lupin/**"]),
        _rule("command", ["query", "reply"], ["ingress", "egress"], ["lupin/**"]),
        _rule("who", LIVELINESS, ["ingress", "egress"], ["lupin/**"]),
        _rule("stop", ["query", "reply"], ["ingress", "egress"], stops),
        _rule("dispatch", ["put", "delete"], ["ingress"], ["lupin/fleet/**"]),
    ]
    if members.consoles:
        subjects.append({"id": "consoles", "cert_common_names": list(members.consoles)})
        policies.append({"rules": ["read", "command", "who"], "subjects": ["consoles"]})
    if members.dispatcher:
        subjects.append({"id": "dispatcher", "cert_common_names": [members.dispatcher]})
        policies.append({"rules": ["read", "command", "who", "dispatch"], "subjects": ["dispatcher"]})
    if members.robots:
        subjects.append({"id": "robots", "cert_common_names": list(members.robots)})
        policies.append({"rules": ["stop"], "subjects": ["robots"]})
    return {"enabled": True, "default_permission": "deny", "rules": rules, "subjects": subjects, "policies": policies}


def router_config(listen: str, tls: TlsFiles | None, members: Members | None) -> zenoh.Config:
    """The router's whole config: listen on ``listen`` (TLS with mutual authentication when
    ``tls``), scouting off, and the fleet's access control when its members are known."""
    conf = session_config("listen", listen, tls, zenoh_mode="router")
    if members is not None:
        conf.insert_json5("access_control", json.dumps(access_control(members)))
    return conf


def open_router(listen: str, tls: TlsFiles | None, members: Members | None) -> zenoh.Session:
    try:
        return zenoh.open(router_config(listen, tls, members))
    except zenoh.ZError as exc:
        raise InputError(f"lupin router --listen {listen}: cannot listen there: {exc}") from None
