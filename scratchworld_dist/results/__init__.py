"""Results of a run directory: rows, Parquet schemas, the journaled store and the manifest."""

from scratchworld_dist.results._events import (
    EVENTS_NAME,
    EventLog,
    JobError,
    JobFinish,
    JobRetry,
    JobStart,
    NodeLost,
    RunEvent,
    SweepEnd,
    SweepStart,
    read_events,
)
from scratchworld_dist.results._kind import KindRows, SharedFiles
from scratchworld_dist.results._manifest import (
    MANIFEST_NAME,
    RegradeInfo,
    RunManifest,
    Session,
    continued,
    git_commit,
    now,
    package_versions,
    read_manifest,
    require_manifest,
    write_manifest,
)
from scratchworld_dist.results._records import JobRecord, record_of, test_rows
from scratchworld_dist.results._rows import JobRow, StepRow, TestRow, shared_image_path
from scratchworld_dist.results._schema import (
    CORE_TABLES,
    SCHEMA_VERSION,
    UnknownTableError,
    row_tables,
    table_model,
    table_schema,
)
from scratchworld_dist.results._store import RunStore, effective_rows, kind_of_run
from scratchworld_dist.results._trajectories import attempt_steps
from scratchworld_dist.results.remote._view import local_file, local_folder

__all__ = [
    "CORE_TABLES",
    "EVENTS_NAME",
    "MANIFEST_NAME",
    "SCHEMA_VERSION",
    "EventLog",
    "JobError",
    "JobFinish",
    "JobRecord",
    "JobRetry",
    "JobRow",
    "JobStart",
    "KindRows",
    "NodeLost",
    "RegradeInfo",
    "RunEvent",
    "RunManifest",
    "RunStore",
    "Session",
    "SharedFiles",
    "StepRow",
    "SweepEnd",
    "SweepStart",
    "TestRow",
    "UnknownTableError",
    "attempt_steps",
    "continued",
    "effective_rows",
    "git_commit",
    "kind_of_run",
    "local_file",
    "local_folder",
    "now",
    "package_versions",
    "read_events",
    "read_manifest",
    "record_of",
    "require_manifest",
    "row_tables",
    "shared_image_path",
    "table_model",
    "table_schema",
    "test_rows",
    "write_manifest",
]
