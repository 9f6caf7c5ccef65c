"""The fleet: several robots, one router, one console (spec/fleet.md).

An application package beside ``mission/``: it uses the link (``mission.link``) and never the
other way round. ``certs`` makes the fleet's certificate authority and each member's key,
``router`` writes the Zenoh router's config (TLS, access control) and runs it, ``names`` says
who is who on the wire.
"""
