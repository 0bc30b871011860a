"""The task-episode kind's own commands: checking a suite (``validate``, ``flakes``, ``evaluate``, ``replay``,
``observe``, ``oracle-plan``) and working on episode runs (``regrade``, ``compare``, ``export``), each registered
as an entry point of ``scratchworld.commands`` (pyproject.toml) and imported when it is looked up."""
