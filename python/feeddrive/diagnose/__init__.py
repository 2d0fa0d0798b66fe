"""Discrepancy diagnosis: which effects of the catalogue (docs/effects.md) a model lacks against measured runs.

``diagnose(runs, model)`` runs the loop (see :mod:`.workflow`) and returns a ``Diagnosis``;
``feeddrive.report.diagnosis.write_diagnosis(diag, out_dir)`` writes its files and report;
``feeddrive diagnose`` is the command. The output schema is in docs/diagnosis.md ("Discrepancy
diagnosis").
"""

from .workflow import Diagnosis, Step, diagnose

__all__ = ["Diagnosis", "Step", "diagnose"]
