"""Report fields added after a report's JSON was published, left out of the dump while unset.

A report of runs that have nothing for such a field (older runs, a flag not given) then prints the same
bytes it printed before the field existed; the published schema still lists the field (optional).
"""

from __future__ import annotations

from typing import Any, ClassVar

from pydantic import BaseModel, SerializerFunctionWrapHandler, model_serializer


class LaterFields(BaseModel):
    """A model whose ``later_fields`` are dumped only when set (not None)."""

    later_fields: ClassVar[tuple[str, ...]] = ()

    @model_serializer(mode="wrap")
    def _leave_out_unset(self, handler: SerializerFunctionWrapHandler):  # noqa: ANN202 (keeps the model's schema)
        data: dict[str, Any] = handler(self)
        return {key: value for key, value in data.items() if value is not None or key not in self.later_fields}
