"""The fleet: several robots, one router, one console (spec/fleet.md).

An application package beside ``mission/``: it uses the link (``mission.link``) and never the
other way round. ``certs`` makes the fleet's certificate authority and each member's key,
``members`` says which names are robots and which consoles, ``router`` writes the Zenoh router's
config (TLS, access control) from them and opens it. For the fleet patrol (issue 34): ``split``
divides a mission's pots between the robots up (the last robot home soonest, aisles whole),
``assign`` turns a mission into one patrol per robot with it, ``aisles`` finds the aisles in
the map, ``aisle_locks`` lets one robot at a time into each (the dispatcher's arbiter on the
router), ``fleet_report`` writes ``fleet.json`` and ``fleet.png``.
"""
