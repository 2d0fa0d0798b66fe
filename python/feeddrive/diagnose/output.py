"""Files of a diagnosis: diagnosis.json, model.json (the confirmed effects), model_all_fits.json
(every fit) and one model file per step.

Schema of diagnosis.json: see docs/diagnosis.md.  The HTML report
with the plots is made by :func:`feeddrive.report.diagnosis.write_diagnosis`.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from ..model_file import save_model
from .diagnosis import Diagnosis


def _clean(obj: Any) -> Any:
    """JSON-safe copy: numpy scalars to Python, non-finite floats to None."""
    if isinstance(obj, dict):
        return {str(k): _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _clean(obj.tolist())
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def diagnosis_json(diag: Diagnosis) -> dict:
    """The JSON document of a diagnosis (docs/diagnosis.md)."""
    return _clean(diag.to_json())


def write_files(diag: Diagnosis, out_dir: str | Path) -> dict:
    """diagnosis.json, model.json (the confirmed effects only), model_all_fits.json (every
    fit) and model_stepK.json in ``out_dir``; returns the document."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    doc = diagnosis_json(diag)
    (out / "diagnosis.json").write_text(
        json.dumps(doc, indent=2, allow_nan=False) + "\n", encoding="utf-8"
    )
    save_model(diag.model_confirmed or diag.model, out / "model.json")
    save_model(diag.model, out / "model_all_fits.json")
    for k, st in enumerate(diag.steps, 1):
        if st.model_after is not None:
            save_model(st.model_after, out / f"model_step{k}.json")
    return doc
