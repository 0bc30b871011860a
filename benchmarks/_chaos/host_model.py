"""The chaos sweeps' replaying model as a process of its own, for a host a benchmark made (a network namespace).

    python benchmarks/_chaos/host_model.py ADDRESS SUITE_DIR

Serves the test OpenAI server (``tests/support/openai_server.py``) on ADDRESS with an ephemeral port,
answering each task's golden trajectory one action per turn, without faults (``ChaoticModel`` at rate 0);
prints its base URL on one line, then serves until it is killed.
"""

from __future__ import annotations

import signal
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # for tests.support.openai_server
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # for _chaos.model

from _chaos.model import ChaoticModel
from scratchworld_dist.suites import load_suite
from tests.support.openai_server import OpenAIServer

REQUEST_TIMEOUT_S = 30.0


def main() -> None:
    address, suite_dir = sys.argv[1], Path(sys.argv[2])
    trajectories = {
        task.instruction: [a.model_dump(mode="json", include={"api", "args"}) for a in task.trajectory() or []]
        for task in load_suite(suite_dir).tasks
    }
    server = OpenAIServer(responder=ChaoticModel(0, 0.0, trajectories, set(), REQUEST_TIMEOUT_S), host=address)
    server.start()
    print(server.url, flush=True)
    signal.pause()


if __name__ == "__main__":
    main()
