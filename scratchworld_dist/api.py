"""The Python API: run a sweep, see its plan, read its results and reports as data.

Everything here is what the command line does, with Python values in and out::

    from scratchworld_dist import api

    result = api.run("configs/demo.yaml", seeds=2, tasks__limit=3)  # keyword: a config field, ``__`` for a dot
    jobs = api.load_results(result.run_dir)                           # a pyarrow Table (or as="pandas"/"polars")
    report = api.report([result.run_dir])                             # the model report --format json dumps

Keyword overrides are validated with the config, as ``--set`` is; rows still in a run's journal (a run in
progress, or one that was killed) are read with the compacted ones.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, overload

import pyarrow as pa
import pyarrow.compute as pc
from pydantic import BaseModel

from scratchworld_dist._plan_preview import PlanPreview, preview_plan
from scratchworld_dist._run_summary import RunSummary
from scratchworld_dist.results import RunStore, effective_rows, require_manifest, row_tables
from scratchworld_dist.results.remote._location import is_remote
from scratchworld_dist.results.remote._view import open_view
from scratchworld_dist.sweep import SweepConfig, SweepOverrides, load_sweep_config, stderr_notice

if TYPE_CHECKING:
    import pandas
    import polars

TableFormat = Literal["pyarrow", "pandas", "polars"]
TABLE_FORMATS: tuple[TableFormat, ...] = ("pyarrow", "pandas", "polars")

RunDirs = str | Path | Sequence[str | Path]
"""One run directory, or several: a single path is never read as a sequence of characters."""


def run_dir_list(run_dirs: RunDirs) -> list[Path]:
    """``run_dirs`` as a list of paths, one path given alone included."""
    if isinstance(run_dirs, str | Path):
        return [Path(run_dirs)]
    return [Path(run_dir) for run_dir in run_dirs]


class RunResult(RunSummary):
    """What ``run`` did (where its results are, what it ran) and its report as data."""

    report: BaseModel
    """The run's report (``RunReport`` for task episodes, the drag or perception table, the audit...)."""


def sweep_config(config: SweepConfig | str | Path, **overrides: Any) -> SweepConfig:
    """A config from a file (or as given), with ``overrides`` as dotted keys (``limits__retries=2``)."""
    values = {key.replace("__", "."): value for key, value in overrides.items()}
    if isinstance(config, SweepConfig):
        data = SweepOverrides(values=values).apply(config.model_dump(mode="json"), stderr_notice)
        return SweepConfig.model_validate(data)
    return load_sweep_config(Path(config), changes=SweepOverrides(values=values))


def plan(config: SweepConfig | str | Path, **overrides: Any) -> PlanPreview:
    """The jobs the sweep would run, per model, agent and mode, against its run directory; starts nothing."""
    return preview_plan(sweep_config(config, **overrides))


def run(config: SweepConfig | str | Path, *, force: bool = False, **overrides: Any) -> RunResult:
    """Run (or resume) the sweep on a private local Ray, or the cluster its ``ray.address`` names."""
    from scratchworld_dist._run import run_sweep  # imports Ray: only when a sweep runs

    summary = run_sweep(sweep_config(config, **overrides), force=force)
    return RunResult(**summary.model_dump(), report=report([summary.run_dir]))


def report(run_dirs: RunDirs, *, force: bool = False) -> BaseModel:
    """The report over ``run_dirs`` (one run directory or several) as data: one kind's own report, or the
    diagnosis over several kinds. ``NotARunDirError`` for a folder that is not a run."""
    from scratchworld_dist.reports import report_data  # the statistics stack: only when a report is asked for

    return report_data(run_dir_list(run_dirs), force=force)


@overload
def load_results(
    run_dir: str | Path, table: str = ..., *, effective: bool = ..., as_: Literal["pyarrow"] = ...
) -> pa.Table: ...


@overload
def load_results(
    run_dir: str | Path, table: str = ..., *, effective: bool = ..., as_: Literal["pandas"]
) -> pandas.DataFrame: ...


@overload
def load_results(
    run_dir: str | Path, table: str = ..., *, effective: bool = ..., as_: Literal["polars"]
) -> polars.DataFrame: ...


def load_results(
    run_dir: str | Path, table: str = "jobs", *, effective: bool = True, as_: TableFormat = "pyarrow"
) -> pa.Table | pandas.DataFrame | polars.DataFrame:
    """One table of a run (``jobs``, ``steps``, ``tests`` or its kind's own, e.g. ``drags``), journal included.
    ``run_dir`` may be a URL (``s3://bucket/run``): its shards are read in the bucket, nothing else is downloaded.

    ``effective``: only each job's counted attempt (its latest with a verdict, else its latest error) among
    the rows of the run as it stands (rows of an older suite or harness left out), as reports count them;
    otherwise every attempt ever recorded. ``NotARunDirError`` for a missing folder or one that is not a run
    (never an empty table), ``ValueError`` for an unknown table or ``as_``.
    """
    if table not in row_tables():
        raise ValueError(f"no table {table!r}: tables are {', '.join(row_tables())}")
    if as_ not in TABLE_FORMATS:
        raise ValueError(f"as_={as_!r}: choose one of {', '.join(TABLE_FORMATS)}")
    path = Path(run_dir) if not is_remote(run_dir) else open_view(str(run_dir))  # s3://...: read in place
    manifest = require_manifest(path)
    store = RunStore(path)
    data = store.read_table(table)
    if effective:
        rows = store.job_rows()
        counted = effective_rows(manifest.current_rows(rows))
        keys = pa.array([f"{row.job_id}#{row.attempt}" for row in counted], pa.string())
        attempt = pc.binary_join_element_wise(data.column("job_id"), pc.cast(data.column("attempt"), pa.string()), "#")
        data = data.filter(pc.is_in(attempt, value_set=keys))
    return _as(data, as_)


def _as(data: pa.Table, fmt: TableFormat) -> pa.Table | pandas.DataFrame | polars.DataFrame:
    if fmt == "pyarrow":
        return data
    try:
        if fmt == "pandas":
            return data.to_pandas()
        import polars

        return polars.from_arrow(data)
    except ImportError as exc:
        raise ImportError(f"as_={fmt!r} needs {exc.name} installed (pip install {exc.name})") from None
