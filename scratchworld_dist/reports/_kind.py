"""What the reports ask of a benchmark kind: its own report over its runs (as text and as data, with the model
whose JSON schema is published), and its part of the diagnosis over runs of several kinds."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from pydantic import BaseModel

from scratchworld_dist.kinds import KindTraits
from scratchworld_dist.reports._diagnosis import DiagnosisPart
from scratchworld_dist.reports._render import ReportFormat


class KindReport(KindTraits):
    """The reports facet of a kind. A kind gives ``report_data``, ``report_model`` and ``render_report`` (or
    ``report`` itself); the defaults are no diagnosis part, and its report's schema as the only one it publishes."""

    def report(self, run_dirs: Sequence[Path], fmt: ReportFormat, *, force: bool) -> tuple[str, list[str]]:
        """This kind's own report over its runs, and its warnings (``RunDirError`` when they cannot be merged)."""
        data = self.report_data(run_dirs, force=force)
        return self.render_report(data, fmt), list(getattr(data, "warnings", []))

    def render_report(self, data: BaseModel, fmt: ReportFormat) -> str:
        """``report_data``'s report as text in ``fmt`` (``md``, ``html`` or ``json``)."""
        raise NotImplementedError(f"benchmark {self.name} has no report")

    def report_data(self, run_dirs: Sequence[Path], *, force: bool) -> BaseModel:
        """This kind's report over its runs as data: the model ``report`` renders (its JSON format is its dump)."""
        raise NotImplementedError(f"benchmark {self.name} has no report")

    def report_model(self) -> type[BaseModel]:
        """The model ``report_data`` returns (its JSON schema is published with the reports')."""
        raise NotImplementedError(f"benchmark {self.name} has no report")

    def tracker_files(self, run_dir: Path) -> dict[str, bytes]:
        """Files besides the report a run hands its experiment trackers at its end (name: content): the tasks
        kind's leaderboard. Default: none."""
        return {}

    def diagnosis(self) -> DiagnosisPart | None:
        """Its columns of the diagnosis table and its section of the report over several kinds (None: none)."""
        return None

    def schemas(self) -> dict[str, type[BaseModel]]:
        """The JSON it writes for other tools, by schema file stem: its report's, and its exports' if any."""
        return {f"{self.name}-report": self.report_model()}
