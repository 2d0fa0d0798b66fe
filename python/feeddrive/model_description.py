"""Where the FMU is, and its variable list as its modelDescription.xml declares it.

modelDescription.xml is the one list of variables (the C table is generated from it at build
time); the Python side reads the same file out of the FMU the package loads, so the units and
the declared ``min``/``max`` of :mod:`feeddrive.physics.params` are the FMU's own.
"""

from __future__ import annotations

import math
import os
import zipfile
from dataclasses import dataclass
from functools import lru_cache
from importlib import resources
from pathlib import Path
from xml.etree import ElementTree

FMU_ENV = "FEEDDRIVE_FMU"
DEFAULT_FMU = Path(str(resources.files(__package__) / "LinearMotorFeedDrive.fmu"))


class FMUError(RuntimeError):
    """An FMI call failed; the message carries what the FMU logged."""


class FMUNotFoundError(FileNotFoundError):
    """No ``.fmu`` where :func:`fmu_path` looked; the message names every place it looked."""


def fmu_path(path: str | Path | None = None) -> Path:
    """The FMU to load: ``path``, else ``$FEEDDRIVE_FMU``, else the package's own copy.

    The package's copy (:data:`DEFAULT_FMU`, package data of the wheel; `make fmu` places it
    there in a checkout).  An explicit ``path`` or ``$FEEDDRIVE_FMU`` that names no file is an
    error, not a fall-back.

    Raises
    ------
    FMUNotFoundError
        One line naming the places looked at.
    """
    if path is not None:
        p = Path(path)
        if not p.is_file():
            raise FMUNotFoundError(f"{p}: no FMU there")
        return p
    env = os.environ.get(FMU_ENV)
    if env:
        p = Path(env)
        if not p.is_file():
            raise FMUNotFoundError(
                f"{FMU_ENV}={env}: no FMU there (the package's own copy, "
                f"used when {FMU_ENV} is unset, would be {DEFAULT_FMU})"
            )
        return p
    if not DEFAULT_FMU.is_file():
        raise FMUNotFoundError(
            f"no FMU: none in the package ({DEFAULT_FMU}) and {FMU_ENV} is not "
            f"set; build it with `make fmu` in the checkout or set {FMU_ENV} "
            f"to a LinearMotorFeedDrive.fmu"
        )
    return DEFAULT_FMU


@dataclass(frozen=True)
class Variable:
    """One scalar variable: ``kind`` is Real, Integer or Boolean; ``lo``/``hi`` the declared
    closed interval (infinite where none is declared)."""

    name: str
    kind: str
    causality: str
    variability: str
    unit: str
    lo: float
    hi: float


def _number(text: str | None, default: float) -> float:
    return default if text is None else float(text)


@lru_cache(maxsize=8)
def _read(path: str, mtime: float) -> dict[str, Variable]:
    try:
        with zipfile.ZipFile(path) as z:
            root = ElementTree.fromstring(z.read("modelDescription.xml"))
    except (OSError, KeyError, zipfile.BadZipFile, ElementTree.ParseError) as e:
        raise ValueError(f"{path}: no readable modelDescription.xml ({e})") from None
    out: dict[str, Variable] = {}
    if root.get("fmiVersion", "").startswith("3"):
        return _read3(root)
    for sv in root.iter("ScalarVariable"):
        typed = next(iter(sv))
        out[sv.get("name", "")] = Variable(
            name=sv.get("name", ""),
            kind=typed.tag,
            causality=sv.get("causality", "local"),
            variability=sv.get("variability", "continuous"),
            unit=typed.get("unit", ""),
            lo=_number(typed.get("min"), -math.inf),
            hi=_number(typed.get("max"), math.inf),
        )
    return out


@lru_cache(maxsize=8)
def _version(path: str, mtime: float) -> str:
    try:
        with zipfile.ZipFile(path) as z:
            root = ElementTree.fromstring(z.read("modelDescription.xml"))
    except (OSError, KeyError, zipfile.BadZipFile, ElementTree.ParseError) as e:
        raise ValueError(f"{path}: no readable modelDescription.xml ({e})") from None
    version = root.get("fmiVersion", "")
    if not version.startswith(("2.", "3.")):
        raise ValueError(f"{path}: fmiVersion = {version!r}: allowed 2.0 or 3.0")
    return version


def fmi_version(fmu: str | Path | None = None) -> str:
    """The ``fmiVersion`` of the FMU file ``fmu`` (default: :func:`fmu_path`): "2.0" or "3.0".

    Raises ValueError naming the file when its modelDescription.xml is unreadable or declares
    another version.
    """
    p = fmu_path(fmu)
    return _version(str(p.resolve()), p.stat().st_mtime)


_KIND3 = {"Float64": "Real", "Int32": "Integer", "Boolean": "Boolean"}


def _read3(root: ElementTree.Element) -> dict[str, Variable]:
    """FMI 3.0 variables under their FMI 2.0 names: an array of dimension ``friction.N``
    as its elements ``friction.F[1]`` ... up to the structural parameter's ``max``."""
    mv = list(root.iterfind("ModelVariables/*"))
    size = {
        v.get("valueReference"): int(v.get("max", v.get("start", "1")))
        for v in mv
        if v.get("causality") == "structuralParameter"
    }
    out: dict[str, Variable] = {}
    for v in mv:
        kind = _KIND3.get(v.tag, v.tag)
        name = v.get("name", "")
        dims = v.findall("Dimension")
        if not dims:
            out[name] = _variable3(v, name, kind)
            continue
        n = size.get(dims[0].get("valueReference"), int(dims[0].get("start", "1")))
        for k in range(1, n + 1):
            el = f"der({name[4:-1]}[{k}])" if name.startswith("der(") else f"{name}[{k}]"
            out[el] = _variable3(v, el, kind)
    return out


def _variable3(v: ElementTree.Element, name: str, kind: str) -> Variable:
    """The FMI 3.0 variable ``v`` (or one element of it) as ``name``."""
    return Variable(
        name=name,
        kind=kind,
        causality=v.get("causality", "local"),
        variability=v.get("variability", "continuous"),
        unit=v.get("unit", ""),
        lo=_number(v.get("min"), -math.inf),
        hi=_number(v.get("max"), math.inf),
    )


def variables(fmu: str | Path | None = None) -> dict[str, Variable]:
    """The variables of the FMU file ``fmu`` (default: :func:`fmu_path`) by name, read once
    per file version."""
    p = fmu_path(fmu)
    return _read(str(p.resolve()), p.stat().st_mtime)
