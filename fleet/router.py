"""The fleet's router: zenoh's own router mode, its config written from the fleet's members.

``lupin router`` opens a Zenoh session in ``router`` mode (the pip wheel runs as a router, so no
``zenohd`` is needed; one installed takes the same config: ``lupin router --write-config FILE``
writes ``router_settings`` as JSON for ``zenohd -c FILE``). It listens
on TLS by default, multicast scouting off, and only members whose certificate the fleet's
authority signed connect (mutual TLS). Access control, by certificate common name, is the
table of spec/fleet.md "Security" (default deny; ``flows`` as seen by the router)::

    who         may
    robot R     publish under lupin/R/**, answer queries on lupin/R/cmd/*, lupin/R/stop and
                lupin/fleet/stop, hold the token lupin/R/alive, read lupin/fleet/**,
                ask for aisles on lupin/fleet/aisles/ask/R (fleet.aisle_locks), read
                where every robot is, lupin/*/where (mission.link.peers: it keeps out of them)
    console     read everything under lupin/**, query any key (commands, stops, history) but
                lupin/fleet/aisles/ask/* (a robot's own: no lock taken in its name), see every
                robot's token; publish nothing, hold no token
    dispatcher  what a console may, and write lupin/fleet/** (assignments, aisle locks), answer
                queries on lupin/fleet/aisles/ask/* (the aisle locks' arbiter)
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
from mission.link.aisle_client import ASK, ask_key
from mission.link.peers import WHERE
from mission.link.session import TlsFiles, tls_settings
from mission.link.wire import FLEET_STOP, alive_key

DEFAULT_LISTEN = "tls/0.0.0.0:7447"


def _rule(rid: str, messages: list[str], flows: list[str], keys: list[str]) -> dict:
    return {"id": rid, "permission": "allow", "messages": messages, "flows": flows, "key_exprs": keys}


def access_control(members: Members) -> dict:
    """zenoh's ``access_control`` section for the fleet (module docstring's table). Each message
    is allowed in the one direction it travels: ``ingress`` from its sender into the router,
    ``egress`` from the router to its receiver, so reading never also grants writing."""
    rules, subjects, policies = [], [], []
    stops = ["lupin/*/stop", FLEET_STOP]
    for r in members.robots:
        own = f"lupin/{r}"
        served = [f"{own}/cmd/**", f"{own}/stop", FLEET_STOP]
        rules += [
            _rule(f"{r}.publish", ["put", "delete"], ["ingress"], [f"{own}/**"]),
            _rule(f"{r}.serve", ["declare_queryable"], ["ingress"], served),
            _rule(f"{r}.asked", ["query"], ["egress"], served),
            _rule(f"{r}.answer", ["reply"], ["ingress"], served),
            _rule(f"{r}.alive", ["liveliness_token"], ["ingress"], [alive_key(r)]),
            _rule(f"{r}.aisles", ["query"], ["ingress"], [ask_key(r)]),
            _rule(f"{r}.aisles.answered", ["reply"], ["egress"], [ask_key(r)]),
        ]
        subjects.append({"id": f"robot {r}", "cert_common_names": [r]})
        own_rules = ("publish", "serve", "asked", "answer", "alive", "aisles", "aisles.answered")
        policies.append({"rules": [f"{r}.{p}" for p in own_rules],
                         "subjects": [f"robot {r}"]})
    rules += [
        _rule("subscribe", ["declare_subscriber"], ["ingress"], ["lupin/**"]),
        _rule("receive", ["put", "delete"], ["egress"], ["lupin/**"]),
        _rule("command", ["query"], ["ingress"], ["lupin/**"]),
        _rule("answered", ["reply"], ["egress"], ["lupin/**"]),
        _rule("who", ["declare_liveliness_subscriber", "liveliness_query"], ["ingress"], ["lupin/**"]),
        _rule("who.told", ["liveliness_token"], ["egress"], ["lupin/**"]),
        _rule("stop", ["query"], ["ingress"], stops),
        _rule("stop.answered", ["reply"], ["egress"], stops),
        _rule("fleet.read", ["declare_subscriber"], ["ingress"], ["lupin/fleet/**"]),
        _rule("fleet.told", ["put", "delete"], ["egress"], ["lupin/fleet/**"]),
        _rule("fleet.write", ["put", "delete"], ["ingress"], ["lupin/fleet/**"]),
        _rule("peers.read", ["declare_subscriber"], ["ingress"], [WHERE]),
        _rule("peers.told", ["put"], ["egress"], [WHERE]),
        {**_rule("aisles.others", ["query"], ["ingress"], [f"{ASK}/*"]), "permission": "deny"},
        _rule("aisles.serve", ["declare_queryable"], ["ingress"], [f"{ASK}/*"]),
        _rule("aisles.asked", ["query"], ["egress"], [f"{ASK}/*"]),
        _rule("aisles.answer", ["reply"], ["ingress"], [f"{ASK}/*"]),
    ]
    reader = ["subscribe", "receive", "command", "answered", "who", "who.told"]
    if members.consoles:
        subjects.append({"id": "consoles", "cert_common_names": list(members.consoles)})
        policies.append({"rules": [*reader, "aisles.others"], "subjects": ["consoles"]})
    if members.dispatcher:
        subjects.append({"id": "dispatcher", "cert_common_names": [members.dispatcher]})
        arbiter = ["aisles.serve", "aisles.asked", "aisles.answer"]
        policies.append({"rules": [*reader, "fleet.write", *arbiter], "subjects": ["dispatcher"]})
    if members.robots:
        subjects.append({"id": "robots", "cert_common_names": list(members.robots)})
        policies.append({"rules": ["stop", "stop.answered", "fleet.read", "fleet.told", "peers.read", "peers.told"],
                         "subjects": ["robots"]})
    return {"enabled": True, "default_permission": "deny", "rules": rules, "subjects": subjects, "policies": policies}


def router_settings(listen: str, tls: TlsFiles | None, members: Members | None) -> dict:
    """The router's whole config as zenoh reads it (``zenohd -c`` takes the same JSON): listen on
    ``listen`` (TLS with mutual authentication when ``tls``), scouting off, and the fleet's
    access control when its members are known."""
    if tls is None and listen.startswith("tls/"):
        raise InputError(f"{listen}: a tls/ endpoint needs the fleet's certificates (--certs DIR)")
    conf = {"mode": "router", "listen": {"endpoints": [listen]}, "scouting": {"multicast": {"enabled": False}}}
    if tls is not None:
        conf["transport"] = {"link": {"tls": tls_settings(tls, "listen")}}
    if members is not None:
        conf["access_control"] = access_control(members)
    return conf


def open_router(listen: str, tls: TlsFiles | None, members: Members | None) -> zenoh.Session:
    try:
        return zenoh.open(zenoh.Config.from_json5(json.dumps(router_settings(listen, tls, members))))
    except zenoh.ZError as exc:
        raise InputError(f"lupin router --listen {listen}: cannot listen there: {exc}") from None
