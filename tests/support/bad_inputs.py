"""The bad-input catalog's inputs met before anything runs: configs, suites of both layouts, project files, arguments.

Everything is built under a test's tmp folder from small real parts (our suite's files, projects
made with the builder), so every case runs without network or upstream data. Each table row is
one case: what to build, the command line, the exit status and the words its message must hold.
The builders here also serve ``tests/support/bad_inputs_runtime.py``; the checks live in
``tests/scratchworld_dist/cli/test_bad_inputs.py``.
"""

from __future__ import annotations

import io
import json
import os
import zipfile
from collections import defaultdict
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import yaml

from scratchworld_dist.results import JobRecord, RunStore, StepRow, TestRow
from tests.conftest import SUITE_DIR
from tests.support.projects import counter_project, with_declared_size, with_entry
from tests.support.small_suites import GOLDEN, TASK, native_suite, upstream_clone

CANARY_ENV = "OPENAI_API_KEY"
CANARY = "sk-bad-input-canary-5e0d7c21b9f4"
"""A key in the environment (and named by configs' ``api_key_env``): no output or file may hold it."""

PASTED = "sk-pasted-into-config-93c1"
"""A key a user wrote into a config by mistake: refused, and never echoed back."""


@dataclass(frozen=True)
class CliCase:
    """One command on one bad input."""

    id: str
    build: Callable[[Path], tuple[list[str], list[str]]]
    """Writes the inputs under the given folder; returns the command line and the culprits the message names."""

    exit: int
    fragment: str
    """Words of the expected message."""

    process: bool = False
    """Run as a real process with a time limit: inputs that once blocked (a FIFO) or read forever (/dev/zero)."""


# -- builders --------------------------------------------------------------------------------------


def write_config(path: Path, **fields: object) -> Path:
    """A sweep config on our suite, writing to ``run`` next to it, with ``fields`` set."""
    config: dict[str, object] = {"name": "bad", "suite": str(SUITE_DIR), "output": str(path.parent / "run")}
    config.update(fields)
    path.write_text(yaml.safe_dump(config))
    return path


def llm_config(path: Path, **model: object) -> Path:
    """An llm sweep whose model reads its key from the canary's variable."""
    return write_config(
        path,
        agent="llm",
        models=[{"model": "openai/gpt-4o", "api_key_env": CANARY_ENV, **model}],
        episodes={"synthetic": {}},
    )


def rebuilt(mutate: Callable[[dict[str, bytes]], None]) -> bytes:
    """The counter project with its entries changed by ``mutate`` (name -> bytes)."""
    source = zipfile.ZipFile(io.BytesIO(counter_project().to_sb3()))
    files = {name: source.read(name) for name in source.namelist()}
    mutate(files)
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, data in files.items():
            archive.writestr(name, data)
    return out.getvalue()


def nested_project(depth: int) -> bytes:
    """A project whose project.json carries an array nested ``depth`` deep."""

    def nest(files: dict[str, bytes]) -> None:
        files["project.json"] = files["project.json"][:-1] + b', "deep": ' + b"[" * depth + b"]" * depth + b"}"

    return rebuilt(nest)


def uncompact(run_dir: Path) -> Path:
    """Turn a run's compacted shards back into the journal segment a killed driver leaves (one line per attempt)."""
    store = RunStore(run_dir)
    steps: dict[tuple[str, int], list[StepRow]] = defaultdict(list)
    tests: dict[tuple[str, int], list[TestRow]] = defaultdict(list)
    for row in store.read_table("steps").to_pylist():
        steps[(row["job_id"], row["attempt"])].append(StepRow.model_validate(row))
    for row in store.read_table("tests").to_pylist():
        tests[(row["job_id"], row["attempt"])].append(TestRow.model_validate(row))
    lines = [
        JobRecord(job=job, steps=steps[(job.job_id, job.attempt)], tests=tests[(job.job_id, job.attempt)])
        for job in store.job_rows()
    ]
    for table in ("jobs", "steps", "tests"):
        (run_dir / table / "part-000001.parquet").unlink()
    segment = run_dir / "journal" / "segment-000001.jsonl"
    segment.write_text("".join(record.model_dump_json() + "\n" for record in lines))
    return segment


def tear_line(segment: Path, index: int) -> None:
    """Cut line ``index`` of a journal segment in half, as a write interrupted by a crash leaves it."""
    lines = segment.read_bytes().splitlines(keepends=True)
    lines[index] = lines[index][: len(lines[index]) // 2]
    segment.write_bytes(b"".join(lines))


# -- configs: ``scratchworld run CONFIG`` ----------------------------------------------------------


def _config_text(text: str | bytes) -> Callable[[Path], tuple[list[str], list[str]]]:
    def build(tmp: Path) -> tuple[list[str], list[str]]:
        path = _write(tmp / "sweep.yaml", text if isinstance(text, bytes) else text.format(suite=SUITE_DIR))
        return ["run", str(path)], [str(path)]

    return build


def _config(culprit: str | None = None, **fields: object) -> Callable[[Path], tuple[list[str], list[str]]]:
    """A config with ``fields``; its message names the config file, or ``culprit`` (what the field points at)."""

    def build(tmp: Path) -> tuple[list[str], list[str]]:
        path = write_config(tmp / "sweep.yaml", **fields)
        return ["run", str(path)], [culprit or str(path)]

    return build


def _config_path(make: Callable[[Path], Path]) -> Callable[[Path], tuple[list[str], list[str]]]:
    def build(tmp: Path) -> tuple[list[str], list[str]]:
        path = make(tmp)
        return ["run", str(path)], [str(path)]

    return build


def _config_suite(make: Callable[[Path], Path]) -> Callable[[Path], tuple[list[str], list[str]]]:
    def build(tmp: Path) -> tuple[list[str], list[str]]:
        suite = make(tmp)
        path = write_config(tmp / "sweep.yaml", suite=str(suite))
        return ["run", str(path)], [str(suite)]

    return build


def _fifo(tmp: Path) -> Path:
    os.mkfifo(tmp / "sweep.yaml")
    return tmp / "sweep.yaml"


def _small_limits(tmp: Path) -> tuple[list[str], list[str]]:
    path = write_config(tmp / "sweep.yaml", tasks={"ids": [TASK]}, project_limits={"max_file_mb": 0.001})
    return ["run", str(path)], [str(GOLDEN)]


CONFIG_CASES = [
    CliCase(
        "yaml-syntax-error",
        _config_text(f"name: x\nsuite: {{suite}}\nmodels:\n  - model: a\n    temperature: 0\n   {PASTED}: [\n"),
        2,
        "not valid YAML: line 6, column 4",
    ),
    CliCase("not-a-mapping", _config_text("- name\n- suite\n"), 2, "must be a mapping of fields"),
    CliCase("empty-file", _config_text(""), 2, "must be a mapping of fields"),
    CliCase("not-utf8", _config_text(b"name: x\n\xff\xfe\n"), 2, "can't decode byte 0xff"),
    CliCase(
        "wrong-types",
        _config(seeds="many", limits={"pages_per_worker": 1.5}),
        2,
        "limits.pages_per_worker: Input should be a valid integer",
    ),
    CliCase("unknown-field", _config(agnet="oracle"), 2, "agnet: unknown key; did you mean 'agent'?"),
    CliCase(
        "secret-in-params",
        _config(agent="llm", models=[{"model": "openai/x", "params": {"extra_headers": {"Authorization": PASTED}}}]),
        2,
        "extra_headers.Authorization may not appear in a config",
    ),
    CliCase(
        "key-value-instead-of-its-name",
        _config(agent="llm", models=[{"model": "openai/x", "api_key_env": PASTED}]),
        2,
        "models.0.api_key_env: Value error, must be the NAME of an environment variable",
    ),
    CliCase("name-with-a-path", _config(name="../../etc"), 2, "name: String should match pattern"),
    CliCase(
        "missing-config", lambda tmp: (["run", str(tmp / "nope.yaml")], [str(tmp / "nope.yaml")]), 2, "cannot read"
    ),
    CliCase("config-is-a-fifo", _config_path(_fifo), 2, "not a regular file", process=True),
    CliCase(
        "config-is-dev-zero", lambda tmp: (["run", "/dev/zero"], ["/dev/zero"]), 2, "not a regular file", process=True
    ),
    CliCase("suite-missing", _config_suite(lambda tmp: tmp / "no-suite"), 2, "no such directory"),
    CliCase("suite-is-a-file", _config_suite(lambda tmp: GOLDEN), 2, "not a directory"),
    CliCase("unknown-task-id", _config("no_such_task", tasks={"ids": ["no_such_task"]}), 2, "no task"),
    CliCase(
        "task-list-on-our-suite",
        _config(str(SUITE_DIR / "suite.json"), tasks={"task_list": "all_tasks"}),
        2,
        "task lists are an upstream-clone feature",
    ),
    CliCase("task-project-over-limits", _small_limits, 2, "over project_limits.max_file_mb"),
    CliCase(
        "ray-address-garbage",
        _config(
            "not an address", ray={"address": "not an address", "connect_timeout_s": 3}, episodes={"synthetic": {}}
        ),
        2,
        "cannot join the Ray cluster at not an address",
    ),
    CliCase(
        "unwritable-output",
        _config("/proc/scratchworld-bad-input", output="/proc/scratchworld-bad-input"),
        2,
        "cannot write results here",
    ),
]


# -- suites: ``scratchworld validate SUITE`` (both layouts) -----------------------------------------


def _native(
    damage: Callable[[Path, Path], Path], task_name: str = TASK
) -> Callable[[Path], tuple[list[str], list[str]]]:
    """A native suite damaged by ``damage(suite, task)``, which returns the culprit."""

    def build(tmp: Path) -> tuple[list[str], list[str]]:
        suite = tmp / "suite"
        culprit = damage(suite, native_suite(suite, task_name))
        return ["validate", str(suite)], [str(culprit)]

    return build


def _upstream(damage: Callable[[Path], Path], *extra: str) -> Callable[[Path], tuple[list[str], list[str]]]:
    """A minimal upstream clone damaged by ``damage(clone)``, which returns the culprit."""

    def build(tmp: Path) -> tuple[list[str], list[str]]:
        clone = upstream_clone(tmp / "ScratchWorld")
        culprit = damage(clone)
        return ["validate", str(clone), *extra], [str(culprit)]

    return build


def _write(path: Path, data: str | bytes) -> Path:
    if isinstance(data, bytes):
        path.write_bytes(data)
    else:
        path.write_text(data)
    return path


def _removed(path: Path) -> Path:
    path.unlink()
    return path


def _replace_with_link(path: Path, target: str) -> Path:
    path.unlink()
    path.symlink_to(target)
    return path


def _upstream_task(clone: Path, **fields: object) -> Path:
    task = {"type": "compute", "instruction": "Add two numbers.", "initial_project": "calc.sb3", **fields}
    return _write(clone / "tasks" / "compute" / "calc.json", json.dumps(task))


def _hostile_upstream_name(clone: Path) -> Path:
    (clone / "tasks" / "compute" / "calc.json").rename(clone / "tasks" / "compute" / "calc\x1b[2J\nforged.json")
    return clone / "tasks" / "compute"


def _hostile_folder(suite: Path, task: Path) -> Path:
    return suite / "compute"


SUITE_CASES = [
    CliCase(
        "task-json-malformed",
        _native(lambda s, t: _write(t / "task.json", '{"instruction": "x",')),
        2,
        "malformed JSON",
    ),
    CliCase(
        "task-json-unknown-key",
        _native(lambda s, t: _write(t / "task.json", '{"instruction": "x", "timeot_s": 3}')),
        2,
        "timeot_s: Extra inputs are not permitted",
    ),
    CliCase(
        "task-json-is-dev-zero",
        _native(lambda s, t: _replace_with_link(t / "task.json", "/dev/zero")),
        2,
        "not a regular file",
        process=True,
    ),
    CliCase("script-missing", _native(lambda s, t: _removed(t / "evaluate.js")), 2, "missing"),
    CliCase(
        "suite-json-not-an-object", _native(lambda s, t: _write(s / "suite.json", "[1, 2]")), 2, "valid dictionary"
    ),
    CliCase(
        "unknown-category-folder",
        _native(lambda s, t: (s / "wizardry").mkdir() or s / "wizardry"),
        2,
        "unknown category folder 'wizardry'",
    ),
    CliCase(
        "task-folder-with-escapes-and-newline",
        _native(_hostile_folder, task_name="sum\x1b[31m\nforged"),
        2,
        "is not a plain name",
    ),
    CliCase("not-a-suite", lambda tmp: (["validate", str(tmp)], [str(tmp)]), 2, "not a task suite"),
    CliCase(
        "suite-name-with-escapes",
        _native(
            lambda s, t: _write(s / "suite.json", json.dumps({"format": "scratchworld_dist/1", "name": "a\x1b[2J\nb"}))
        ),
        2,
        "name: String should match pattern",
    ),
    CliCase(
        "upstream-unknown-type",
        _upstream(lambda clone: _upstream_task(clone, type="wizardry")),
        2,
        "unknown category 'wizardry'",
    ),
    CliCase(
        "upstream-project-outside-the-clone",
        _upstream(lambda clone: _upstream_task(clone, initial_project="../../../../etc/hostname")),
        2,
        "is outside scratch-gui/static/",
    ),
    CliCase(
        "upstream-helper-missing",
        _upstream(
            lambda clone: _removed(clone / "scratch-bench-api" / "api" / "evaluation_scripts" / "evaluation_utils.js")
        ),
        2,
        "missing: upstream scripts need the helper module",
    ),
    CliCase(
        "upstream-task-list-malformed",
        _upstream(
            lambda clone: _write(clone / "tasks" / "15_tasks.json", '{"compute": "calc.json"}'),
            "--task-list",
            "15_tasks",
        ),
        2,
        "a task list must look like",
    ),
    CliCase(
        "upstream-task-list-unknown",
        _upstream(lambda clone: clone / "tasks" / "no_list.json", "--task-list", "no_list"),
        2,
        "missing",
    ),
    CliCase("upstream-task-file-with-escapes", _upstream(_hostile_upstream_name), 2, "is not a plain name"),
]


# -- projects: ``scratchworld evaluate SUITE TASK PROJECT`` and ``observe PROJECT`` -----------------


def _project(
    data: bytes | Callable[[], bytes], command: str = "evaluate"
) -> Callable[[Path], tuple[list[str], list[str]]]:
    def build(tmp: Path) -> tuple[list[str], list[str]]:
        path = tmp / "bad project.sb3"
        path.write_bytes(data() if callable(data) else data)
        args = ["observe", str(path)] if command == "observe" else ["evaluate", str(SUITE_DIR), TASK, str(path)]
        return args, [str(path)]

    return build


def _sparse_over_limit(tmp: Path) -> tuple[list[str], list[str]]:
    path = tmp / "huge.sb3"
    with path.open("wb") as handle:
        handle.truncate(65 * 1024 * 1024)  # sparse: no disk, but past the 64 MiB limit
    return ["evaluate", str(SUITE_DIR), TASK, str(path)], [str(path)]


_LYING_BOMB = lambda: with_declared_size(  # noqa: E731
    with_entry(counter_project().to_sb3(), "big.wav", bytes(70 * 1024 * 1024)), "big.wav", 1000
)

PROJECT_CASES = [
    CliCase("empty", _project(b""), 3, "project_invalid"),
    CliCase("not-a-zip", _project(b"hello, I am a text file"), 3, "not an .sb3 zip archive"),
    CliCase("corrupt-zip", _project(b"PK\x03\x04" + bytes(100)), 3, "not a readable zip archive"),
    CliCase(
        "truncated",
        _project(lambda: GOLDEN.read_bytes()[: GOLDEN.stat().st_size // 2]),
        3,
        "not a readable zip archive",
    ),
    CliCase("no-project-json", _project(lambda: rebuilt(lambda f: f.pop("project.json"))), 3, "has no project.json"),
    CliCase(
        "project-json-garbage",
        _project(lambda: rebuilt(lambda f: f.update({"project.json": b'{"targets": [1,'}))),
        3,
        "project.json is not valid JSON",
    ),
    CliCase("nested-5000-deep", _project(lambda: nested_project(5000)), 3, "RecursionError"),
    CliCase("entry-lies-about-its-size", _project(_LYING_BOMB), 3, "'big.wav' inflates past the limit"),
    CliCase(
        "archive-bomb",
        _project(lambda: with_entry(counter_project().to_sb3(), "big.wav", bytes(70 * 1024 * 1024))),
        3,
        "'big.wav' is 70.00 MiB, over the limit of 64 MiB (project_limits.max_entry_mb)",
    ),
    CliCase("file-over-the-limit", _sparse_over_limit, 2, "larger than 64 MiB"),
    CliCase(
        "project-is-dev-zero",
        lambda tmp: (["evaluate", str(SUITE_DIR), TASK, "/dev/zero"], ["/dev/zero"]),
        2,
        "not a regular file",
        process=True,
    ),
    CliCase("observe-corrupt", _project(b"PK\x03\x04" + bytes(100), "observe"), 2, "not a readable zip archive"),
]


# -- command-line arguments -------------------------------------------------------------------------


def _args(*args: str, culprit: str) -> Callable[[Path], tuple[list[str], list[str]]]:
    return lambda tmp: ([arg.format(tmp=tmp) for arg in args], [culprit.format(tmp=tmp)])


ARGUMENT_CASES = [
    CliCase("unknown-command", _args("frobnicate", culprit="frobnicate"), 2, "No such command"),
    CliCase("unknown-option", _args("report", "{tmp}", "--frob", culprit="--frob"), 2, "No such option"),
    CliCase("missing-argument", _args("run", culprit="CONFIG_FILE"), 2, "Missing argument"),
    CliCase("wrong-type", _args("validate", str(SUITE_DIR), "--parallel", "many", culprit="--parallel"), 2, "'many'"),
    CliCase(
        "out-of-range",
        _args("validate", str(SUITE_DIR), "--parallel", "0", culprit="--parallel"),
        2,
        "not in the range",
    ),
    CliCase("bad-choice", _args("report", "{tmp}", "--format", "pdf", culprit="--format"), 2, "'pdf' is not one of"),
    CliCase(
        "directory-for-a-file", _args("evaluate", str(SUITE_DIR), TASK, "{tmp}", culprit="{tmp}"), 2, "is a directory"
    ),
    CliCase("file-for-a-directory", _args("status", str(GOLDEN), culprit=str(GOLDEN)), 2, "is a file"),
    CliCase(
        "missing-trajectory",
        _args("replay", str(SUITE_DIR), TASK, "{tmp}/none.json", culprit="none.json"),
        2,
        "does not exist",
    ),
    CliCase(
        "unknown-task",
        _args("evaluate", str(SUITE_DIR), "no_such_task", str(GOLDEN), culprit="no_such_task"),
        2,
        "no task",
    ),
    CliCase(
        "json-into-a-directory",
        _args("evaluate", str(SUITE_DIR), TASK, str(GOLDEN), "--json", "{tmp}", culprit="{tmp}"),
        2,
        "is a directory",
    ),
    CliCase(
        "unwritable-json",
        lambda tmp: (
            [
                "evaluate",
                str(SUITE_DIR),
                TASK,
                str(_write(tmp / "corrupt.sb3", b"PK\x03\x04")),
                "--json",
                "/proc/bad/x.json",
            ],
            ["/proc/bad/x.json"],
        ),
        2,
        "No such file or directory",
    ),
    CliCase(
        "malformed-trajectory",
        lambda tmp: (
            ["replay", str(SUITE_DIR), TASK, str(_write(tmp / "t.json", '[{"api": "add_block", "args": [1]}]'))],
            [str(tmp / "t.json")],
        ),
        2,
        'not a list of {"api", "args"} actions',
    ),
]
