"""Errors a user can cause (a bad file, a bad option, a missing device).

They carry one clear message naming what and where; the CLI prints it on one line and exits 2.
Errors that are bugs stay ordinary exceptions, so they keep their tracebacks.
"""


class InputError(Exception):
    """Bad input from a user: the message alone must tell them what to fix."""
