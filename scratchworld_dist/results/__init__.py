"""Results of a run directory: rows, Parquet schemas, the journaled store and the manifest."""

from scratchworld_dist.results._manifest import (
    MANIFEST_NAME,
    RegradeInfo,
    RunManifest,
    Session,
    SuiteInfo,
    continued,
    git_commit,
    now,
    package_versions,
    read_manifest,
    require_manifest,
    write_manifest,
)
from scratchworld_dist.results._records import (
    DragRow,
    JobRecord,
    JobRow,
    PerceptionRow,
    StepRow,
    TestRow,
    record_of,
    shared_image_path,
    test_rows,
)
from scratchworld_dist.results._schema import SCHEMA_VERSION, SCHEMAS, TABLES
from scratchworld_dist.results._store import RunStore, effective_rows

__all__ = [
    "MANIFEST_NAME",
    "SCHEMAS",
    "SCHEMA_VERSION",
    "TABLES",
    "DragRow",
    "JobRecord",
    "JobRow",
    "PerceptionRow",
    "RegradeInfo",
    "RunManifest",
    "RunStore",
    "Session",
    "StepRow",
    "SuiteInfo",
    "TestRow",
    "continued",
    "effective_rows",
    "git_commit",
    "now",
    "package_versions",
    "read_manifest",
    "record_of",
    "require_manifest",
    "shared_image_path",
    "test_rows",
    "write_manifest",
]
