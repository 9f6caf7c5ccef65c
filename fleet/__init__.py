"""The fleet: several robots, one router, one console (spec/fleet.md).

An application package beside ``mission/``: it uses the link (``mission.link``) and never the
other way round. ``certs`` makes the fleet's certificate authority and each member's key,
``members`` says which names are robots and which consoles, ``router`` writes the Zenoh router's
config (TLS, access control) from them and opens it.
"""
