"""Virtual experiments on the FMU that produce runs exactly as a measurement would."""
