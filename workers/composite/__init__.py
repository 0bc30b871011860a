"""Composite mode: the text observation of the project and the semantic block-editing API."""

from workers.composite._observation import (
    MAX_CHOICES,
    CatalogBlock,
    CatalogField,
    CatalogInput,
    block_catalog,
    execute,
    observe,
    render_catalog,
    sync_workspace,
)

__all__ = [
    "MAX_CHOICES",
    "CatalogBlock",
    "CatalogField",
    "CatalogInput",
    "block_catalog",
    "execute",
    "observe",
    "render_catalog",
    "sync_workspace",
]
