"""The JSON schemas of the reports as data (``report --format json``, ``scratchworld_dist.api.report``) and of the
ATIF trajectories ``export`` writes.

Published in ``docs/schemas/`` (``scratchworld schemas docs/schemas`` writes them; a test checks the files are
current), so a reader of a report's JSON in another language knows its shape without reading our code.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from scratchworld_dist.kinds import job_kinds
from scratchworld_dist.reports._diagnosis_report import DiagnosisReport


def report_schemas() -> dict[str, dict[str, Any]]:
    """Each report's JSON schema by its file name (every installed kind's own, the diagnosis over kinds) and
    the ATIF trajectory's."""
    from scratchworld_dist.kinds.tasks.exports import ATIF_VERSION, AtifTrajectory  # exports build on the reports

    models = {f"{kind.name}-report": kind.report_model() for kind in job_kinds()}
    models["diagnosis-report"] = DiagnosisReport
    models[f"atif-{ATIF_VERSION.removeprefix('ATIF-').lower()}"] = AtifTrajectory  # ``export --format atif``
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
