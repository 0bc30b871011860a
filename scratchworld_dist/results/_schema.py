"""Arrow schemas of the tables, derived from the row models so the two never drift."""

from __future__ import annotations

import types
from datetime import datetime
from functools import cache
from typing import Any, Union, get_args, get_origin

import pyarrow as pa
from pydantic import BaseModel

from scratchworld_dist.kinds import job_kinds
from scratchworld_dist.results._rows import JobRow, StepRow, TestRow

SCHEMA_VERSION = 5
"""Bumped on any change to a table; stored in every shard's metadata. 4: ``jobs.benchmark``; 5: ``tests.unstable``."""

CONTINUABLE_SCHEMAS = frozenset({3, 4, 5})
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


CORE_TABLES: dict[str, type[BaseModel]] = {"jobs": JobRow, "steps": StepRow, "tests": TestRow}
"""The tables of every run, by folder name: each kind adds its own (``KindTraits.tables``)."""

KIND_TABLE_KEYS = ("job_id", "attempt")
"""Columns a kind's own table must have: its rows belong to one attempt of one job."""


class UnknownTableError(ValueError):
    """A table name neither the core nor an installed kind defines."""


@cache
def row_tables() -> dict[str, type[BaseModel]]:
    """Every table a run directory may hold, and its row model: the core ones, then each installed kind's."""
    tables = dict(CORE_TABLES)
    for kind in job_kinds():
        for name, model in kind.tables.items():
            missing = [key for key in KIND_TABLE_KEYS if key not in model.model_fields]
            if missing:
                raise UnknownTableError(f"benchmark {kind.name}: table {name} lacks column(s) {', '.join(missing)}")
            if tables.setdefault(name, model) is not model:
                raise UnknownTableError(f"benchmark {kind.name}: table {name} is another table's name already")
    return tables


def table_model(name: str) -> type[BaseModel]:
    """The row model of table ``name``; ``UnknownTableError`` names the tables there are."""
    tables = row_tables()
    if name not in tables:
        raise UnknownTableError(f"no result table {name!r} (tables: {', '.join(tables)})")
    return tables[name]


@cache
def table_schema(name: str) -> pa.Schema:
    """The Arrow schema of table ``name``, derived from its row model."""
    return arrow_schema(table_model(name))
