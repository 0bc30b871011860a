"""The tokens an episode's model calls are taken to use before any run of the suite measured them (``plan``'s
default estimate; docs/sweeps.md, "Cost before spending").

Per step: the system prompt (the action API and the task), up to ``llm.history_messages`` earlier turns and the
newest observation. Composite mode observes the project as text; primitive mode the newest screenshot and the element
list. The input figures are LiteLLM's token counts of the requests our llm agent sent in ``benchmarks/plan_estimate.py``
on four tasks of our suite (composite 3,800-6,300 per step, primitive 3,100-3,900), rounded; a model's reply (the
output) is taken at 250 tokens, a short analysis and the action (the benchmark's scripted replies are shorter). An
attempt is taken to use half its step budget: the real figure depends on the model and the task (measured runs,
``plan --tokens-from``, replace all of these).
"""

from __future__ import annotations

from scratchworld_dist.sweep import TokenRates

EPISODE_RATES: dict[str, TokenRates] = {
    "composite": TokenRates(
        input_per_step=6_000, output_per_step=250, source="default for composite episodes (docs/sweeps.md)"
    ),
    "primitive": TokenRates(
        input_per_step=4_000, output_per_step=250, source="default for primitive episodes (docs/sweeps.md)"
    ),
}
"""Per mode: tokens per step, half the step budget per attempt, one attempt per job."""
