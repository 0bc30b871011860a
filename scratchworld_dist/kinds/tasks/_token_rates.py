"""The tokens an episode's model calls are taken to use before any run of the suite measured them (``plan``'s
default estimate; docs/sweeps.md, "Cost before spending").

Per step: the system prompt (the action API and the task), up to ``llm.history_messages`` earlier turns and the
newest observation. Composite mode observes the project as text; primitive mode a screenshot (about 1,100 tokens at
1280x720 for GPT-4o-class models) and the element list. Figures measured with ``benchmarks/plan_estimate.py`` on our
suite (LiteLLM's token counter on the requests our llm agent sends), rounded up; a model's own replies (the output)
are taken at 250 tokens, a short analysis and the action. An attempt is taken to use half its step budget.
"""

from __future__ import annotations

from scratchworld_dist.sweep import TokenRates

EPISODE_RATES: dict[str, TokenRates] = {
    "composite": TokenRates(
        input_per_step=6_000, output_per_step=250, source="default for composite episodes (docs/sweeps.md)"
    ),
    "primitive": TokenRates(
        input_per_step=9_000, output_per_step=250, source="default for primitive episodes (docs/sweeps.md)"
    ),
}
"""Per mode: tokens per step, half the step budget per attempt, one attempt per job."""
