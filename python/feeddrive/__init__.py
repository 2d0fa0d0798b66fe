"""feeddrive: a linear-motor feed drive (Villegas et al. 2014) as an FMI 2.0 FMU, and the
Python workflow around it: model, experiments, identification, control, diagnosis, report."""

__version__ = "0.1.0"
