"""A yes / no question before a command that cannot be undone (clearing the map).

Dismissed with True (y) or False (n, escape). The app's priority keys (driving, the e-stop)
still work while it is up: a question never stands between the operator and the stop.
"""
from __future__ import annotations

from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Vertical
from textual.screen import ModalScreen
from textual.widgets import Label


class Confirm(ModalScreen[bool]):
    BINDINGS = [Binding("y", "answer(True)", "yes"), Binding("n", "answer(False)", "no"),
                Binding("escape", "answer(False)", "no", show=False)]

    def __init__(self, question: str):
        super().__init__()
        self.question = question

    def compose(self) -> ComposeResult:
        with Vertical(id="confirm"):
            yield Label(self.question)
            yield Label("y = yes, n = no")

    def action_answer(self, yes: bool) -> None:
        self.dismiss(yes)
