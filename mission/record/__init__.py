"""Foxglove for a patrol: one module decides the channels (``channels``), two sinks use them:
an MCAP file beside the report (``mcap_file``, ``lupin patrol --record``) and the live
WebSocket server (``live``)."""
