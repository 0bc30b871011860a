"""Arrow schemas of the tables, derived from the row models so the two never drift."""

from __future__ import annotations

import types
from datetime import datetime
from typing import Any, Union, get_args, get_origin

import pyarrow as pa
from pydantic import BaseModel

from scratchworld_dist.results._records import DragRow, JobRow, PerceptionRow, StepRow, TestRow

SCHEMA_VERSION = 4
"""Bumped on any change to a table; stored in every shard's metadata. 4: ``jobs.benchmark``."""

CONTINUABLE_SCHEMAS = frozenset({3, 4})
"""Schemas whose run directories this code reads and adds to: each later one only adds nullable columns,
which the older shards read as null (see ``RunStore.job_rows``)."""

_ARROW_TYPES: dict[Any, pa.DataType] = {
    str: pa.string(),
    int: pa.int64(),
    float: pa.float64(),
    bool: pa.bool_(),
    datetime: pa.timestamp("us", tz="UTC"),
}


def _field(name: str, annotation: Any) -> pa.Field:
    nullable = False
    if get_origin(annotation) in (Union, types.UnionType):
        args = [a for a in get_args(annotation) if a is not type(None)]
        nullable = len(args) < len(get_args(annotation))
        (annotation,) = args
    return pa.field(name, _ARROW_TYPES[annotation], nullable=nullable)


def arrow_schema(model: type[BaseModel]) -> pa.Schema:
    fields = [_field(name, info.annotation) for name, info in model.model_fields.items()]
    return pa.schema(fields, metadata={"scratchworld_schema_version": str(SCHEMA_VERSION)})


TABLES: dict[str, type[BaseModel]] = {
    "jobs": JobRow,
    "steps": StepRow,
    "tests": TestRow,
    "drags": DragRow,
    "perception": PerceptionRow,
}
"""Folder name of each table in a run directory, and its row model."""

SCHEMAS: dict[str, pa.Schema] = {name: arrow_schema(model) for name, model in TABLES.items()}
