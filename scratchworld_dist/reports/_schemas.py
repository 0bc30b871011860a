"""The reports' JSON as other tools read it: the schemas of the reports as data (``report --format json``,
``scratchworld_dist.api.report``) and of what the kinds export (the ATIF trajectories of episodes), and report
fields added after a report's JSON was published.

The schemas are published in ``docs/schemas/`` (``scratchworld schemas docs/schemas`` writes them; a test checks
the files are current), so a reader of a report's JSON in another language knows its shape without reading our
code. A field added later (``LaterFields``) is left out of the dump while unset: a report of runs that have
nothing for it (older runs, a flag not given) prints the same bytes it printed before the field existed, and the
published schema still lists the field (optional).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, ClassVar

from pydantic import BaseModel, SerializerFunctionWrapHandler, model_serializer

from scratchworld_dist.kinds import job_kinds
from scratchworld_dist.reports._diagnosis_report import diagnosis_models
from scratchworld_dist.reports._kind import KindReport


def report_schemas() -> dict[str, dict[str, Any]]:
    """Each report's JSON schema by its file name: what every installed kind publishes (its report's, its
    exports'), and the diagnosis over kinds."""
    models = {name: model for kind in job_kinds(KindReport) for name, model in kind.schemas().items()}
    models["diagnosis-report"] = diagnosis_models().report
    return {f"{name}.schema.json": model.model_json_schema(mode="serialization") for name, model in models.items()}


def write_report_schemas(folder: Path) -> list[Path]:
    """Write the schemas into ``folder``; returns the files written."""
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    for name, schema in report_schemas().items():
        path = folder / name
        path.write_text(json.dumps(schema, indent=2, sort_keys=True) + "\n", encoding="utf-8")
        written.append(path)
    return written


class LaterFields(BaseModel):
    """A model whose ``later_fields`` are dumped only when set (not None)."""

    later_fields: ClassVar[tuple[str, ...]] = ()

    @model_serializer(mode="wrap")
    def _leave_out_unset(self, handler: SerializerFunctionWrapHandler):  # noqa: ANN202 (keeps the model's schema)
        data: dict[str, Any] = handler(self)
        return {key: value for key, value in data.items() if value is not None or key not in self.later_fields}
