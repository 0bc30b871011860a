"""The JSON schemas of the reports as data (``report --format json``, ``scratchworld_dist.api.report``) and of what
the kinds export (the ATIF trajectories of episodes).

Published in ``docs/schemas/`` (``scratchworld schemas docs/schemas`` writes them; a test checks the files are
current), so a reader of a report's JSON in another language knows its shape without reading our code.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from scratchworld_dist.kinds import job_kinds
from scratchworld_dist.reports._diagnosis_report import DiagnosisReport
from scratchworld_dist.reports._kind import KindReport


def report_schemas() -> dict[str, dict[str, Any]]:
    """Each report's JSON schema by its file name: what every installed kind publishes (its report's, its
    exports'), and the diagnosis over kinds."""
    models = {name: model for kind in job_kinds(KindReport) for name, model in kind.schemas().items()}
    models["diagnosis-report"] = DiagnosisReport
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
