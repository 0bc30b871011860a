"""The parts of ``benchmarks/chaos.py``: the local cluster, the faulty model, the fault schedule, the checks."""
