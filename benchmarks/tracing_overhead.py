"""Prints what tracing costs a composite step: the demo's composite episodes (oracle) run in one worker, each
untraced and traced in turn (the order alternating), and the spans of one step timed alone.

    .venv/bin/python benchmarks/tracing_overhead.py [--rounds 2] [--tasks 12]

Traced means what ``OTEL_EXPORTER_OTLP_ENDPOINT`` turns on: the SDK's tracer provider, a batch span processor and
the OTLP/HTTP exporter, sending to a sink on 127.0.0.1 in another process (a collector's stand-in that answers
200), with the attempt's ``traceparent`` in the job as the driver sends it. Untraced is the API's no-op tracer.
Step time is each step's ``latency_s`` (observe, act, apply); the target is under 1% of it. On a loaded machine the
episodes' difference is mostly noise (the spread of the pairs' ratios shows how much); the spans' own cost is also
given as CPU time (the exporter's thread included), which other processes' load does not inflate as wall time.
"""

from __future__ import annotations

import argparse
import asyncio
import statistics
import subprocess
import sys
import time
from pathlib import Path

from opentelemetry import trace

from scratchworld_dist.sweep import load_sweep_config, plan_run, worker_job
from workers.actor import JobWorker
from workers.tracing import set_attributes, span, traceparent_of

REPO = Path(__file__).resolve().parents[1]

SINK = (
    "import http.server, sys\n"
    "class Sink(http.server.BaseHTTPRequestHandler):\n"
    "    def do_POST(self):\n"
    "        self.rfile.read(int(self.headers.get('Content-Length', 0)))\n"
    "        self.send_response(200); self.send_header('Content-Length', '0'); self.end_headers()\n"
    "    def log_message(self, *args): pass\n"
    "server = http.server.ThreadingHTTPServer(('127.0.0.1', 0), Sink)\n"
    "print(server.server_address[1], flush=True)\n"
    "server.serve_forever()\n"
)


def traced_provider(port: int) -> object:
    from opentelemetry.exporter.otlp.proto.http.trace_exporter import OTLPSpanExporter
    from opentelemetry.sdk.resources import Resource
    from opentelemetry.sdk.trace import TracerProvider
    from opentelemetry.sdk.trace.export import BatchSpanProcessor

    provider = TracerProvider(resource=Resource.create({"service.name": "tracing-overhead"}))
    provider.add_span_processor(BatchSpanProcessor(OTLPSpanExporter(endpoint=f"http://127.0.0.1:{port}/v1/traces")))
    return provider


def use(provider: object | None) -> None:
    """Spans from here on go to ``provider`` (None: the API's no-op tracer), as if the process had started so."""
    trace._TRACER_PROVIDER = provider  # type: ignore[attr-defined]  # a benchmark's switch, not an API


def step_spans_us(provider: object | None, steps: int = 2_000, tries: int = 3) -> tuple[float, float]:
    """Microseconds the spans of one step cost (step and action, with their attributes, inside an episode span),
    their export to the sink included (flushed every 500 steps, within the batch queue): wall and CPU time (this
    process's, the exporter's thread included), the best of ``tries`` each."""
    use(provider)
    flush = getattr(provider, "force_flush", lambda: True)
    wall, cpu = float("inf"), float("inf")
    for _ in range(tries):
        started, started_cpu = time.perf_counter(), time.process_time()
        with span("episode", task="t"):
            for index in range(steps):
                with span("step", index=index, task="t", mode="composite") as stepping:
                    with span("action", action="add_block") as acting:
                        set_attributes(acting, ok=True, error_code=None)
                    set_attributes(stepping, action="add_block", ok=True, llm_calls=0, input_tokens=0, output_tokens=0)
                if index % 500 == 499:
                    flush()
        flush()
        wall = min(wall, (time.perf_counter() - started) / steps * 1e6)
        cpu = min(cpu, (time.process_time() - started_cpu) / steps * 1e6)
    use(None)
    return wall, cpu


async def episodes(rounds: int, limit: int, provider: object) -> tuple[dict[bool, list[float]], list[float]]:
    """Step latencies (s) of the demo's composite jobs, untraced (False) and traced (True); and for each job and
    round, its mean traced step over its mean untraced step (a pair run back to back, which goes first alternating)."""
    plan = plan_run(load_sweep_config(REPO / "configs" / "demo.yaml"))
    jobs = [job for job in plan.jobs if job.mode == "composite"][:limit]
    payloads = {content.task.id: content.payload for content in plan.contents}
    steps: dict[bool, list[float]] = {False: [], True: []}
    ratios: list[float] = []
    worker = JobWorker(worker_index=0)
    try:
        await worker.run(worker_job(jobs[0], 1, 300), payloads[jobs[0].task_id])  # the browser's start, untimed
        for round_index in range(rounds):
            for number, job in enumerate(jobs):
                means: dict[bool, float] = {}
                for traced in (True, False) if (round_index + number) % 2 else (False, True):
                    use(provider if traced else None)
                    sent = worker_job(job, 1, 300)
                    opened = trace.get_tracer("driver").start_span("job", attributes={"task": job.task_id})
                    sent = sent.model_copy(update={"trace_parent": traceparent_of(opened)})
                    result = await worker.run(sent, payloads[job.task_id])
                    opened.end()
                    if result.outcome != "passed":
                        raise RuntimeError(f"{job.task_id}: {result.outcome} {result.error_message}")
                    steps[traced].extend(step.latency_s for step in result.steps)
                    means[traced] = statistics.fmean(step.latency_s for step in result.steps)
                ratios.append(means[True] / means[False])
            print(f"round {round_index + 1}/{rounds}: {len(jobs)} task(s) each way", file=sys.stderr)
    finally:
        use(None)
        await worker.close()
    return steps, ratios


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--tasks", type=int, default=12, help="the demo's first N composite jobs")
    args = parser.parse_args()
    sink = subprocess.Popen([sys.executable, "-c", SINK], stdout=subprocess.PIPE, text=True)
    try:
        port = int(sink.stdout.readline())  # type: ignore[union-attr]
        provider = traced_provider(port)
        found, ratios = asyncio.run(episodes(args.rounds, args.tasks, provider))
        micro_off, micro_on = step_spans_us(None), step_spans_us(provider)
        provider.shutdown()  # type: ignore[attr-defined]
    finally:
        sink.kill()
    off_steps, on_steps = found[False], found[True]
    off_mean, on_mean = statistics.fmean(off_steps), statistics.fmean(on_steps)
    print(f"composite steps: {len(off_steps)} untraced, {len(on_steps)} traced ({args.tasks} demo task(s) x "
          f"{args.rounds} round(s), each run untraced and traced back to back)")  # fmt: skip
    print(f"step time untraced: mean {off_mean * 1000:.2f} ms, median {statistics.median(off_steps) * 1000:.2f} ms")
    print(f"step time traced:   mean {on_mean * 1000:.2f} ms, median {statistics.median(on_steps) * 1000:.2f} ms")
    quartiles = statistics.quantiles(ratios, n=4) if len(ratios) > 1 else [ratios[0]] * 3
    print(f"traced / untraced mean step, per pair: geometric mean {statistics.geometric_mean(ratios):.3f}, "
          f"median {quartiles[1]:.3f}, quartiles {quartiles[0]:.3f}-{quartiles[2]:.3f} over {len(ratios)} pairs "
          "(the spread is the machine's noise)")  # fmt: skip
    (wall_off, cpu_off), (wall_on, cpu_on) = micro_off, micro_on
    print(f"spans of one step (step, action, attributes, export): wall {wall_on:.1f} us traced, {wall_off:.1f} us "
          f"no-op; CPU {cpu_on:.1f} us traced, {cpu_off:.1f} us no-op")  # fmt: skip
    for what, cost in (("CPU", cpu_on - cpu_off), ("wall", wall_on - wall_off)):
        share = cost / (off_mean * 1e6) * 100
        print(f"tracing's {what} cost per step: {cost:.1f} us = {share:.3f}% of the mean untraced step (target < 1%)")


if __name__ == "__main__":
    main()
