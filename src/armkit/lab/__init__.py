"""``armkit lab``: the seed reports' experiments end to end, verified in MuJoCo, as an HTML report."""

from armkit.lab.run import LabResult, run_lab

__all__ = ["LabResult", "run_lab"]
