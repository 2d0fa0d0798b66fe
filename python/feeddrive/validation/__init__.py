"""Closed-loop validation of a model against a measured run: the run's reference replayed
through the model and its controller (:mod:`.replay`)."""
