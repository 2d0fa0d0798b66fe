"""Analyses of measured data from other machines (read-only, in ``DIR/realdata`` of ``--shared DIR``).

- :mod:`feeddrive.realdata.odrive` -- a rotary BLDC motor's measured cogging maps and slow runs
  (ODrive, G. Chen): position spectrum, short-time position spectrum (the paper's DSTFT),
  crosstalk line, friction from forward/reverse maps, slow-run correlation and velocity ripple.
"""

from .odrive import OdriveFindings, analyse, findings_text

__all__ = ["OdriveFindings", "analyse", "findings_text"]
