"""Virtual experiments on the FMU that produce runs exactly as a measurement would, and the
paper's closed-loop scenarios.

- the identification campaign (:mod:`.campaign`, one module per experiment);
- :mod:`.sec3`: Sec. 3 (Fig. 14), the measured sinusoid against model variants;
- :mod:`.sec4`: Sec. 4 (Figs. 15-16), state-space control with and without feedforward;
- :mod:`.reproduction`: the controller design, a timed run, Secs. 3 and 4 (``feeddrive run``);
- :mod:`.tracking_error`: the tracking-error measures around reversals and elsewhere.
"""
