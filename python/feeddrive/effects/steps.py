"""What an effect's identification step receives from the identification pipeline.

An effect whose parameters ``feeddrive identify`` fits in a step of its own declares the
step in its module (:attr:`~feeddrive.effects.effect.Identification.run`, a function of an
:class:`IdentificationHost`); the pipeline (:mod:`feeddrive.identify.pipeline`) implements the
host and runs the steps in their declared order.  The host hands the step the services of
the higher layers: the campaign's runs by kind, the fits by reference, the parameters
identified so far.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Protocol


class IdentificationHost(Protocol):
    """The identification pipeline as an effect's step sees it."""

    @property
    def params(self) -> dict[str, Any]:
        """The model's FMU-named parameters as the steps so far identified them (the paper's
        values until then); one mapping, the same object on every call."""
        ...

    @property
    def dc_gain(self) -> float | None:
        """G(1) [A/V] for runs without a current column (i = G(1) u), else None."""
        ...

    @property
    def current_timing(self) -> str:
        """How a recorded current sample relates to the force (``physics.held_current``)."""
        ...

    @property
    def prerolling_elements(self) -> int:
        """N of the Maxwell-slip model to identify."""
        ...

    @property
    def profile_knots(self) -> int:
        """Knots of a friction-level profile to identify."""
        ...

    def runs(self, kind: str) -> list[Any]:
        """The campaign's runs of sidecar kind ``kind``, in the given order."""
        ...

    def fit(self, label: str, reference: str, *args: Any, **kw: Any) -> Any:
        """Call the fit ``reference`` (``"module:function"``) with the arguments; a
        ValueError it raises is raised again naming the step ``label``."""
        ...

    def take(self, values: Mapping[str, float]) -> None:
        """Take identified FMU parameters into the model."""
        ...

    def skip(self, label: str, why: str) -> None:
        """Record that the step ``label`` was skipped and why."""
        ...

    def note(self, line: str) -> None:
        """Add a line to the identification's notes."""
        ...
