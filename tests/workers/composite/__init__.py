"""Composite mode in a real editor, in two modules sharing this folder's conftest (page, project, calls)."""
