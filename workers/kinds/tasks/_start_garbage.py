"""The garbage of an episode's start, collected once its page first waits for a model.

Loading the project and running its first second leave garbage that V8 collects only when it gets round to it:
tens of seconds later in a page that waits, which is what an agent's page does while its model answers (a
waiting editor holds about 35 MB less once collected). A forced collection costs the page's renderer about 0.27
CPU-s, and an episode that never waits (the oracle, scripted agents) gains nothing by it: its page collects as
it goes. So the collection begins with the episode's first model call and runs while the model answers.
"""

from __future__ import annotations

import asyncio

from workers._held_tasks import hold
from workers.editor import Editor


class StartGarbage:
    """Collects one page's start garbage at most once, beside whatever the episode does meanwhile."""

    def __init__(self, editor: Editor) -> None:
        self.editor = editor
        self._collecting: asyncio.Future[None] | None = None
        self._ended = False

    def collect(self) -> None:
        """Begin the collection, the first time only and not after ``end`` (a call in the agent's finish); it runs
        while the model answers."""
        if self._collecting is None and not self._ended:
            self._collecting = asyncio.ensure_future(self.editor.collect_garbage())

    def end(self) -> None:
        """As the agent's part ends: a collection still under way is stopped, not waited for (the page no longer
        waits, and a page stuck in a loop would hold the episode up); its error, if any, is dropped."""
        self._ended = True
        collecting, self._collecting = self._collecting, None
        if collecting is not None:
            collecting.cancel()  # nothing, once it is done
            hold(collecting)  # until it ends; a crashed page is told by the episode's next use of it (its save)
