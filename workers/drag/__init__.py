"""The single-step drag benchmark inside a worker: set up the view, compute the exact regions, ask, drag, verify."""
