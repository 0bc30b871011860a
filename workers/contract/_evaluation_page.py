"""Whether an evaluation script needs the editor page, or the bare evaluation page serves it.

The bare page (``scratch-gui/bare.html``) has the VM, the renderer and the audio engine, and no editor
GUI. A script that reaches for the editor's DOM or its block editor cannot run there, and is detected
from its source (and its helper's) before any page opens: a mention of ``document``, ``ScratchBlocks``
or ``Blockly``, a DOM query or React's internals sends its evaluations to the editor page
(``EvaluationSpec`` does so itself). None of our tasks and none of the upstream scripts in ``../shared``
mention any.
"""

from __future__ import annotations

import re

_GUI_NAMES = re.compile(
    r"\b(document|ScratchBlocks|Blockly|querySelector(?:All)?|getElementsBy\w+|getElementById|__reactFiber\w*|ReactDOM)\b"
)


def editor_need(*sources: str | None) -> str | None:
    """The first name in ``sources`` that only the editor page has, or None when the bare page serves."""
    for source in sources:
        found = _GUI_NAMES.search(source or "")
        if found:
            return found.group(1)
    return None
