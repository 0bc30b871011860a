"""A perception suite: the items that loaded (and the views ours were made of), and a one-line problem for
everything that did not."""

from __future__ import annotations

from scratchworld_dist._errors import TaskNotFoundError
from scratchworld_dist.kinds.perception.items._item import PerceptionItem, PerceptionView
from scratchworld_dist.suites import BaseSuite


class PerceptionSuite(BaseSuite[PerceptionItem]):
    """The items found in one folder, in suite order; screenshot and project paths are absolute."""

    views: tuple[PerceptionView, ...] = ()

    def item(self, item_id: str) -> PerceptionItem:
        for item in self.items:
            if item.id == item_id:
                return item
        if why := self.left_out(item_id):
            raise TaskNotFoundError(f"perception item {item_id!r} of suite {self.name} was left out: {why}")
        raise TaskNotFoundError(f"no perception item {item_id!r} in suite {self.name} ({self.root})")

    def view(self, view_id: str) -> PerceptionView:
        for view in self.views:
            if view.id == view_id:
                return view
        raise TaskNotFoundError(f"no view {view_id!r} in perception suite {self.name} ({self.root})")
