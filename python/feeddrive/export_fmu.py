"""A model file as its own plant FMU, and the same values as an SSP parameter set.

:func:`export_fmu` copies the plant FMU (FMI 2.0 or 3.0) with everything it carries (every
``binaries/`` platform folder, ``sources/``, documentation) and changes three things:

- ``modelDescription.xml``: the ``start`` of every parameter of the model file (effect
  switches included) is the model's, the description names the model, its file and the file's
  date, and ``generationDateAndTime`` is the export's time; the FMI 3.0 arrays sized by
  ``friction.N`` get the model's N elements;
- ``resources/start_values.txt``: the same values, ``name value`` per line (FMI 2.0 names,
  floats with ``repr`` digits).  The FMU's binary reads it when instantiated
  (``fmu_src/models/plant/start_values.c``), so the FMU starts as the model also in an importer that sets
  no parameters; the binary is the source FMU's, unchanged (so is its GUID/instantiation token).

Beside the ``.fmu`` goes ``<stem>.ssv``, an SSP 1.0 parameter set (``ssv:ParameterSet``) of the
same values, with their units, for co-simulation engines that take one.  fmpy does the unzip
(:func:`fmpy.extract`) and the zip (:func:`fmpy.util.create_zip_archive`); lxml edits the XML.
"""

from __future__ import annotations

import datetime as dt
import re
import tempfile
from dataclasses import dataclass
from pathlib import Path

from fmpy import extract
from fmpy.util import create_zip_archive
from lxml import etree

from .fmu3 import DEFAULT_FMU3
from .model_description import fmu_path
from .model_file import INTEGER_PARAMETERS, ModelFile, Value, load_model
from .outputs import OutputError, check_file, write_with

#: the file in the FMU's resources/ whose values the binary takes as start values
START_VALUES = "start_values.txt"
SSV = "http://ssp-standard.org/SSP1/SystemStructureParameterValues"
SSC = "http://ssp-standard.org/SSP1/SystemStructureCommon"
_ELEMENT = re.compile(r"(.+)\[(\d+)\]")
_BASE_UNITS = ("kg", "m", "s", "A", "K", "mol", "cd", "rad", "factor", "offset")


@dataclass(frozen=True)
class Exported:
    """What :func:`export_fmu` wrote: the FMU, the parameter set, the FMI version."""

    fmu: Path
    ssv: Path
    fmi: int


def literal(name: str, value: Value) -> str:
    """``value`` as the text of an FMI/SSP start value: true/false, an integer, or the
    shortest decimal that reads back as the same float64 (``repr``)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if name in INTEGER_PARAMETERS:
        return str(int(value))
    return repr(float(value))


def source_fmu(fmi: int) -> Path:
    """The plant FMU an export of FMI version ``fmi`` (2 or 3) starts from."""
    if fmi == 2:
        return fmu_path()
    if fmi == 3:
        return fmu_path(DEFAULT_FMU3)
    raise ValueError(f"--fmi {fmi}: allowed 2 or 3")


def ssv_path(out: str | Path) -> Path:
    """The parameter set written beside the FMU ``out``: ``<stem>.ssv``."""
    out = Path(out)
    return out.with_suffix(".ssv")


def _set_start2(root: etree._Element, values: dict[str, Value], src: Path) -> None:
    found = set()
    for sv in root.iter("ScalarVariable"):
        name = sv.get("name")
        if name in values:
            typed = next(iter(sv))
            typed.set("start", literal(name, values[name]))
            found.add(name)
    _all_found(values, found, src)


def _set_start3(root: etree._Element, values: dict[str, Value], src: Path) -> None:
    mv = root.find("ModelVariables")
    sizes: dict[str, int] = {}
    for v in mv:
        if v.get("causality") == "structuralParameter" and v.get("name") in values:
            sizes[v.get("valueReference")] = int(values[v.get("name")])
    found = set()
    for v in mv:
        name = v.get("name")
        dims = v.findall("Dimension")
        if not dims:
            if name in values:
                v.set("start", literal(name, values[name]))
                found.add(name)
            continue
        if len(dims) != 1 or v.get("start") is None:
            continue
        ref = dims[0].get("valueReference")
        n = sizes.get(ref) if ref is not None else int(dims[0].get("start"))
        elements = [f"{name}[{k}]" for k in range(1, n + 1)] if n is not None else []
        if elements and all(e in values for e in elements):
            v.set("start", " ".join(literal(e, values[e]) for e in elements))
            found.update(e for e in values if (m := _ELEMENT.fullmatch(e)) and m.group(1) == name)
    _all_found(values, found, src)


def _all_found(values: dict[str, Value], found: set[str], src: Path) -> None:
    missing = [n for n in values if n not in found]
    if missing:
        raise ValueError(
            f"{src}: has no parameter {missing[0]!r} of the model file "
            f"({len(missing)} missing): export from the FMU of this feeddrive"
        )


def _describe(model: ModelFile, model_path: Path | None) -> str:
    what = f"{model.name}" + (f": {model.description}" if model.description else "")
    if model_path is None:
        return f"Identified machine {what} (feeddrive fmu)"
    date = dt.datetime.fromtimestamp(model_path.stat().st_mtime, dt.UTC)
    return (
        f"Identified machine {what}; model file {model_path.name} of "
        f"{date.strftime('%Y-%m-%dT%H:%M:%SZ')} (feeddrive fmu)"
    )


def _edit_description(xml: Path, model: ModelFile, model_path: Path | None, src: Path) -> None:
    tree = etree.parse(str(xml))
    root = tree.getroot()
    values = model.fmu_parameters()
    if root.get("fmiVersion", "").startswith("3"):
        _set_start3(root, values, src)
    else:
        _set_start2(root, values, src)
    root.set(
        "description", f"{_describe(model, model_path)}. Built on: {root.get('description', '')}"
    )
    root.set("generationDateAndTime", dt.datetime.now(dt.UTC).strftime("%Y-%m-%dT%H:%M:%SZ"))
    tree.write(str(xml), encoding="UTF-8", xml_declaration=True)


def start_values_text(model: ModelFile, model_path: Path | None = None) -> str:
    """The ``resources/start_values.txt`` of ``model``: a comment line, then ``name value``."""
    lines = [f"# {_describe(model, model_path)}: start values of the parameters, FMI 2.0 names"]
    lines += [f"{k} {literal(k, v)}" for k, v in model.fmu_parameters().items()]
    return "\n".join(lines) + "\n"


def _units(xml: Path) -> tuple[dict[str, str], dict[str, dict[str, str]]]:
    """variable (FMI 2.0 name) -> unit, and unit -> its base-unit exponents, from the FMU's XML."""
    root = etree.parse(str(xml)).getroot()
    units = {
        u.get("name"): dict(b.attrib) if (b := u.find("BaseUnit")) is not None else {}
        for u in root.iter("Unit")
    }
    of: dict[str, str] = {}
    if root.get("fmiVersion", "").startswith("3"):
        for v in root.find("ModelVariables"):
            if v.get("unit"):
                of[v.get("name")] = v.get("unit")
    else:
        for sv in root.iter("ScalarVariable"):
            unit = next(iter(sv)).get("unit")
            if unit:
                of[sv.get("name")] = unit
    return of, units


def ssv_bytes(model: ModelFile, xml: Path) -> bytes:
    """The SSP 1.0 parameter set of ``model`` (FMI 2.0 names; array elements of an FMI 3.0
    FMU as ``name[k]``), each Real with its unit, the units defined by their SI base units."""
    of, units = _units(xml)
    root = etree.Element(
        f"{{{SSV}}}ParameterSet", nsmap={"ssv": SSV, "ssc": SSC}, version="1.0", name=model.name
    )
    if model.description:
        root.set("description", model.description)
    params = etree.SubElement(root, f"{{{SSV}}}Parameters")
    used: list[str] = []
    for name, value in model.fmu_parameters().items():
        p = etree.SubElement(params, f"{{{SSV}}}Parameter", name=name)
        if isinstance(value, bool):
            etree.SubElement(p, f"{{{SSV}}}Boolean", value=literal(name, value))
        elif name in INTEGER_PARAMETERS:
            etree.SubElement(p, f"{{{SSV}}}Integer", value=literal(name, value))
        else:
            m = _ELEMENT.fullmatch(name)
            unit = of.get(name) or (of.get(m.group(1)) if m else None)
            el = etree.SubElement(p, f"{{{SSV}}}Real", value=literal(name, value))
            if unit:
                el.set("unit", unit)
                if unit not in used:
                    used.append(unit)
    if used:
        us = etree.SubElement(root, f"{{{SSV}}}Units")
        for u in used:
            ue = etree.SubElement(us, f"{{{SSC}}}Unit", name=u)
            etree.SubElement(
                ue,
                f"{{{SSC}}}BaseUnit",
                {k: v for k, v in units.get(u, {}).items() if k in _BASE_UNITS},
            )
    return etree.tostring(root, encoding="UTF-8", xml_declaration=True, pretty_print=True)


def check_outputs(
    out: str | Path, inputs: list[str | Path | None], force: bool
) -> tuple[Path, Path]:
    """The FMU and parameter-set paths for ``out``, checked before any work: a ``.fmu`` name,
    neither an input, neither existing unless ``force``."""
    out = Path(out)
    if out.suffix.lower() != ".fmu":
        raise OutputError(f"{out}: --out must name a .fmu file (the .ssv goes beside it)")
    ssv = ssv_path(out)
    for path in (out, ssv):
        check_file(path, inputs)
        if path.exists() and not force:
            raise OutputError(f"{path}: exists; give --force to replace it, or another --out")
    return out, ssv


def export_fmu(
    model: ModelFile,
    out: str | Path,
    fmi: int = 2,
    *,
    model_path: str | Path | None = None,
    force: bool = False,
    source: str | Path | None = None,
) -> Exported:
    """Write ``model`` as the plant FMU ``out`` (FMI ``fmi``: 2 or 3) and ``<stem>.ssv``.

    ``model_path``: the model file (named in the description, with its date); ``source``: the
    FMU to start from (default :func:`source_fmu`).  Both files are replaced atomically;
    an existing one only with ``force``.  Raises :class:`~feeddrive.outputs.OutputError` (a
    ValueError) for an output that must not be written, ValueError for an FMU that lacks a
    parameter of the model.
    """
    src = fmu_path(source) if source is not None else source_fmu(fmi)
    model_path = Path(model_path) if model_path is not None else None
    fmu, ssv = check_outputs(out, [model_path, src], force)
    with tempfile.TemporaryDirectory(prefix="feeddrive_export_") as tmp:
        unzipped = Path(extract(str(src), str(Path(tmp) / "fmu")))
        xml = unzipped / "modelDescription.xml"
        version = etree.parse(str(xml)).getroot().get("fmiVersion", "")
        if not version.startswith(str(fmi)):
            raise ValueError(f"{src}: fmiVersion {version}, not FMI {fmi}")
        _edit_description(xml, model, model_path, src)
        (unzipped / "resources").mkdir(exist_ok=True)
        (unzipped / "resources" / START_VALUES).write_text(
            start_values_text(model, model_path), encoding="utf-8", newline="\n"
        )
        ssv_data = ssv_bytes(model, xml)
        write_with(fmu, lambda p: create_zip_archive(p, unzipped), [model_path, src])
    write_with(ssv, lambda p: p.write_bytes(ssv_data), [model_path, src])
    return Exported(fmu, ssv, fmi)


def fmu_command(model_path: str | Path, out: str | Path, fmi: int = 2, force: bool = False) -> str:
    """``feeddrive fmu``: export the model file ``model_path`` to ``out`` and ``<stem>.ssv``
    (outputs checked before the model is read); returns the line to print."""
    check_outputs(out, [model_path, source_fmu(fmi)], force)
    model = load_model(model_path)
    done = export_fmu(model, out, fmi, model_path=model_path, force=force)
    return (
        f"wrote {done.fmu} (FMI {fmi}.0, model {model.name!r}: {len(model.fmu_parameters())} "
        f"start values) and {done.ssv} (SSP parameter set)"
    )


__all__ = [
    "Exported",
    "START_VALUES",
    "check_outputs",
    "export_fmu",
    "fmu_command",
    "literal",
    "source_fmu",
    "ssv_bytes",
    "ssv_path",
    "start_values_text",
]
