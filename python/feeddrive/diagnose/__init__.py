"""Discrepancy diagnosis: which effects of EFFECTS.md a model lacks against measured runs.

``diagnose(runs, model, out_dir)`` runs the loop (see :mod:`.workflow`); ``run_cli(argv)`` is
the ``feeddrive diagnose`` command; the output schema is in the README ("Discrepancy diagnosis").
"""
from .cli import run_cli
from .workflow import Diagnosis, Step, diagnose

__all__ = ["Diagnosis", "Step", "diagnose", "run_cli"]
