"""The closed loop (reference -> controller FMU -> plant FMU) in standard system form: an SSP
1.0 package, an OSP system structure (libcosim) and a fmpy container FMU, and the engines
that run them (:mod:`.engines`)."""

from .closed_loop import ClosedLoopSystem, sec3_system, sec4_system
from .engines import run_container, run_fmpy_ssp, run_libcosim_osp, run_libcosim_ssp
from .files import write_all, write_container, write_osp, write_ssp

__all__ = [
    "ClosedLoopSystem",
    "sec3_system",
    "sec4_system",
    "run_container",
    "run_fmpy_ssp",
    "run_libcosim_osp",
    "run_libcosim_ssp",
    "write_all",
    "write_container",
    "write_osp",
    "write_ssp",
]
