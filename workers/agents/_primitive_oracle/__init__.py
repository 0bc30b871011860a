"""The primitive oracle: solves a task through pixels only, by acting out its golden trajectory.

It proves the drag mechanics of primitive mode: every composite action of the golden trajectory
becomes real clicks, drags, wheel turns and key presses, aimed at block geometry read live from the
page (``scratch-gui/geometry/``), and the editor alone decides what a gesture does (snap, insert, bump).

How it works:

1. ``begin`` replays the trajectory through the composite API on the page (the *dry run*,
   ``_plan``) to learn which block every index argument denotes (the trajectory's indices depend on
   positions, which differ in a GUI run) and the semantic project state after every step; then it
   reloads the initial project.
2. ``act`` hands out one gesture at a time (``_targets``, ``_palette``, ``_moves``, ``_fields``).
   Between gestures it only *reads* the page (``_page``, its replies typed in ``_geometry`` and
   ``_state``); it never writes to the VM or the workspace.
3. After every step the GUI project must mean exactly what the dry run's did (scripts, fields,
   variables; not ids or positions), checked with a bounded wait. A gesture without the expected
   effect raises ``OracleDivergenceError`` with what differs, so the oracle never silently goes on.
"""

from workers.agents._primitive_oracle._agent import PrimitiveOracle
from workers.agents._primitive_oracle._divergence import OracleDivergenceError, OracleWaitError
from workers.agents._primitive_oracle._plan import PlannedStep

__all__ = ["OracleDivergenceError", "OracleWaitError", "PlannedStep", "PrimitiveOracle"]
