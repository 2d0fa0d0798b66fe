"""The X-Y table and its ISO 230-4 circular test.

- :mod:`.machine`: the two axes, each its own parameter set;
- :mod:`.path`: the circle's reference on two axes;
- :mod:`.table`: several axes (controller FMU + plant FMU each) stepped by one master;
- :mod:`.circle_test`: the test's cases run and evaluated;
- :mod:`.circular`: the ISO 230-4 evaluation (centre, radial deviation, glitches);
- :mod:`.system`: the same test as an OSP system structure for libcosim.
"""
