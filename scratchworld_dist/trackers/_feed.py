"""``TrackerFeed``: the run's events carried to its trackers off the scheduler's thread.

Each tracker has a lane: a queue and a thread of its own. ``hear`` only puts the event on every lane's queue, so the
scheduler never waits on a tracker, and one tracker that hangs holds up no other. A lane sends the metrics after
``every_results`` attempts or ``every_s`` seconds, and at the end the report and leaderboard. A tracker that raises
is said once and dropped; the sweep goes on as if it had none. At the end the run waits for its lanes at most
``finish_timeout_s``.
"""

from __future__ import annotations

import queue
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass

from scratchworld_dist.results import RunEvent
from scratchworld_dist.sweep._loggers import Loggers
from scratchworld_dist.trackers._tally import PlannedJob, RunTally
from scratchworld_dist.trackers._tracker import RunInfo, Tracker, redacted

Artifacts = Callable[[], dict[str, bytes]]
"""Makes the files attached at the end (name: content): called in a lane's thread, once for all lanes."""


@dataclass(frozen=True)
class _End:
    status: str
    artifacts: Artifacts


class _Lane:
    """One tracker's queue and thread."""

    def __init__(self, tracker: Tracker, feed: TrackerFeed) -> None:
        self.tracker = tracker
        self.feed = feed
        self.events: queue.SimpleQueue[RunEvent | _End] = queue.SimpleQueue()
        self.run_id: str | None = None
        self.failed = False
        self.thread = threading.Thread(target=self._work, name=f"tracker-{tracker.name}", daemon=True)

    def _work(self) -> None:
        doing = "starting its run"
        try:
            self.run_id = self.tracker.start(self.feed.run)
            tally = RunTally(self.feed.planned)
            for event in self.feed.earlier:
                tally.hear(event)
            doing = "logging metrics"
            self.tracker.log_metrics(tally.metrics(), len(tally.decided))
            end = self._follow(tally)
            self.tracker.log_metrics(tally.metrics(), len(tally.decided))
            doing = "attaching the report"
            files = self.feed.artifacts_once(end.artifacts)
            if files:
                self.tracker.log_artifacts(files)
            doing = "closing its run"
            self.tracker.finish(end.status)
        except Exception as exc:  # a tracker never fails the sweep: said once, then left out
            self.failed = True
            detail = (str(exc).strip().splitlines() or [type(exc).__name__])[0][:300]
            self.feed.say(f"tracker {self.tracker.name} failed {doing}: {type(exc).__name__}: {redacted(detail)}; "
                          "the run goes on without it")  # fmt: skip

    def _follow(self, tally: RunTally) -> _End:
        """Count events until the end, sending metrics every ``every_results`` attempts or ``every_s`` seconds."""
        loggers = self.feed.loggers
        pending, last = 0, time.monotonic()
        while True:
            wait = loggers.every_s - (time.monotonic() - last)
            try:
                item = self.events.get(timeout=max(wait, 0.0)) if pending else self.events.get()
            except queue.Empty:
                item = None
            if isinstance(item, _End):
                return item
            if item is not None and tally.hear(item):
                pending += 1
            if pending and (pending >= loggers.every_results or time.monotonic() - last >= loggers.every_s):
                self.tracker.log_metrics(tally.metrics(), len(tally.decided))
                pending, last = 0, time.monotonic()


class TrackerFeed:
    """Carries a run's events to its trackers (see the module's docstring)."""

    def __init__(
        self,
        trackers: list[Tracker],
        run: RunInfo,
        planned: dict[str, PlannedJob],
        earlier: list[RunEvent],
        loggers: Loggers,
        say: Callable[[str], None],
    ) -> None:
        """``earlier``: the run directory's events before this session (its metrics go on from them); ``say``
        prints a line in the run's log (called from the lanes' threads)."""
        self.run = run
        self.planned = planned
        self.earlier = earlier
        self.loggers = loggers
        self.say = say
        self._artifacts: dict[str, bytes] | None = None
        self._artifacts_lock = threading.Lock()
        self.lanes = [_Lane(tracker, self) for tracker in trackers]
        for lane in self.lanes:
            lane.thread.start()

    def hear(self, event: RunEvent) -> None:
        """Pass ``event`` on to every tracker; returns at once."""
        for lane in self.lanes:
            if not lane.failed:
                lane.events.put(event)

    def artifacts_once(self, make: Artifacts) -> dict[str, bytes]:
        """The end's files, made by the first lane that asks."""
        with self._artifacts_lock:
            if self._artifacts is None:
                try:
                    self._artifacts = make()
                except Exception as exc:  # no report is no reason to lose the metrics
                    self._artifacts = {}
                    self.say(f"trackers: the report could not be made for them: {type(exc).__name__}: {exc}")
            return self._artifacts

    def finish(self, status: str, artifacts: Artifacts) -> dict[str, str]:
        """End every lane (``status``: how the sweep ended) and wait at most ``finish_timeout_s`` for them; the
        tracker run ids that were opened, by tracker name."""
        end = _End(status, artifacts)
        for lane in self.lanes:
            lane.events.put(end)
        deadline = time.monotonic() + self.loggers.finish_timeout_s
        for lane in self.lanes:
            lane.thread.join(timeout=max(deadline - time.monotonic(), 0.0))
            if lane.thread.is_alive() and not lane.failed:
                lane.failed = True
                self.say(
                    f"tracker {lane.tracker.name} was still busy {self.loggers.finish_timeout_s:g} s after the run "
                    "ended; left behind (the run's results are complete, its tracker run may lack its end)"
                )
        return {lane.tracker.name: lane.run_id for lane in self.lanes if lane.run_id is not None}
