"""Fits that identification and diagnosis share (below both in the import layers): each
needs only numpy, scipy and :mod:`feeddrive.physics`.

- :mod:`.compliance`: the load's f, zeta, m2 from a rigid model's force residual.
"""
