"""scratchworld_dist: the driver side of the ScratchWorld batch evaluator."""

import os

# Keep a local Ray on the loopback interface: with this 0, Ray takes 127.0.0.1 as this machine's address.
# Ray reads it once, when it is imported, and the package's modules import Ray in any order, so it is set
# here, before any of them. A sweep's private Ray is kept on loopback even when it is 1
# (scheduling/_ray_runtime.py); with 1, Ray places a driver that joins a cluster by this machine's address.
os.environ.setdefault("RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER", "0")


from scratchworld_dist._errors import (
    BridgeError,
    ChromiumNotFoundError,
    EditorBundleMissingError,
    EditorCrashedError,
    EditorError,
    EditorNotReadyError,
    ProjectFormatError,
    ProjectTooLargeError,
    RendererUnavailableError,
    ScratchWorldError,
    SuiteError,
    TaskNotFoundError,
)
from scratchworld_dist._validation import ProjectCheck, TaskValidation, validate_tasks
from scratchworld_dist.suites import Suite, Task, TaskCategory, load_suite

__all__ = [
    "BridgeError",
    "ChromiumNotFoundError",
    "EditorBundleMissingError",
    "EditorCrashedError",
    "EditorError",
    "EditorNotReadyError",
    "ProjectCheck",
    "ProjectFormatError",
    "ProjectTooLargeError",
    "RendererUnavailableError",
    "ScratchWorldError",
    "Suite",
    "SuiteError",
    "Task",
    "TaskCategory",
    "TaskNotFoundError",
    "TaskValidation",
    "load_suite",
    "validate_tasks",
]
