"""The Weights & Biases tracker (``loggers: {wandb: ...}``): its run id is the run directory's key, so a resumed run
continues it (``resume="allow"``); offline, it writes the run's files under ``dir`` for ``wandb sync``. Needs the
``wandb`` extra."""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import Any

from scratchworld_dist.sweep._loggers import WandbLogger
from scratchworld_dist.trackers._tracker import RunInfo

_EXIT_CODES = {"finished": 0, "interrupted": 130, "failed": 1}

MAX_TAG_CHARS = 64
"""W&B's limit on a tag (the run's ``key=value`` labels are cut to it)."""


class WandbTracker:
    name = "wandb"

    def __init__(self, settings: WandbLogger) -> None:
        self.settings = settings
        self.run: Any = None

    def start(self, run: RunInfo) -> str:
        import wandb  # the extra, imported only for a run that logs to W&B

        settings = self.settings
        if settings.dir is not None:
            settings.dir.mkdir(parents=True, exist_ok=True)
        self.run = wandb.init(
            project=settings.project or run.name,
            entity=settings.entity,
            id=run.key,
            resume="allow",
            name=run.name,
            mode=settings.mode,
            dir=str(settings.dir) if settings.dir is not None else None,
            config=run.params,
            tags=[(f"{k}={v}" if v else k)[:MAX_TAG_CHARS] for k, v in run.tags.items()],
            reinit="create_new",  # its own run object: the user's runs in this process are left alone
            settings=wandb.Settings(console="off", silent=True, x_disable_stats=True),
        )
        return str(self.run.id)

    def log_metrics(self, metrics: dict[str, float], step: int) -> None:
        self.run.log(metrics)  # W&B's own step counts logs; the decided count is a metric of its own

    def log_artifacts(self, files: dict[str, bytes]) -> None:
        import wandb

        artifact = wandb.Artifact(f"{self.run.id}-report", type="report")
        with tempfile.TemporaryDirectory(prefix="scratchworld-wandb-") as folder:
            for name, content in files.items():
                path = Path(folder) / name
                path.write_bytes(content)
                artifact.add_file(str(path), name=name)
            self.run.log_artifact(artifact)  # add_file copied each file to W&B's staging: the folder may go

    def finish(self, status: str) -> None:
        self.run.finish(exit_code=_EXIT_CODES.get(status, 0))
