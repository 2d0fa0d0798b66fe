"""A corpus of bad run CSVs, sidecars and model files, made from one good run and model.

``csv_cases(good_csv)``, ``sidecar_cases(good_sidecar)`` and ``model_cases(good_model)``
return ``(name, file text or bytes)`` pairs; every one breaks a rule of DATA.md, of the run
sidecar schema (``feeddrive.harness.sidecar``), of the model file format or of the FMU's
parameter ranges, or is a run the tools must refuse (implausible sampling, too short,
overflowing values, signals that carry nothing).
"""

from __future__ import annotations

import json
from typing import Any


def _lines(text: str) -> list[str]:
    return text.splitlines()


def _join(lines: list[str]) -> str:
    return "\n".join(lines) + "\n"


def _set_cell(text: str, line: int, column: str, value: str) -> str:
    """``text`` with the cell of ``column`` on 1-based ``line`` replaced by ``value``."""
    lines = _lines(text)
    k = lines[0].split(",").index(column)
    cells = lines[line - 1].split(",")
    cells[k] = value
    lines[line - 1] = ",".join(cells)
    return _join(lines)


def _map_column(text: str, column: str, fn) -> str:
    lines = _lines(text)
    k = lines[0].split(",").index(column)
    out = [lines[0]]
    for row, ln in enumerate(lines[1:]):
        cells = ln.split(",")
        cells[k] = fn(row, cells[k])
        out.append(",".join(cells))
    return _join(out)


def csv_cases(good: str) -> list[tuple[str, str | bytes]]:
    """Bad run files made from the text of a good run (columns time,u,i,x,x_ref,F_load)."""
    lines = _lines(good)
    header = lines[0]
    n = len(lines) - 1
    mid = n // 2
    cases: list[tuple[str, str | bytes]] = [
        ("empty", ""),
        ("header_only", header + "\n"),
        ("one_row", _join(lines[:2])),
        ("two_rows", _join(lines[:3])),
        ("ten_rows", _join(lines[:11])),
        (
            "missing_x",
            _join([",".join(c for c in ln.split(",")[:3] + ln.split(",")[4:]) for ln in lines]),
        ),
        ("missing_time_case", _join(["Time" + lines[0][4:]] + lines[1:])),
        ("duplicate_column", _join([header.replace("x_ref", "x")] + lines[1:])),
        ("text_cell", _set_cell(good, mid, "u", "abc")),
        ("empty_cell", _set_cell(good, mid, "i", "")),
        ("nan_x", _set_cell(good, mid, "x", "nan")),
        ("inf_u", _set_cell(good, 5, "u", "inf")),
        ("minus_inf_time", _set_cell(good, n + 1, "time", "-Infinity")),
        ("time_backwards", _set_cell(good, mid, "time", "0.0001")),
        ("time_repeats", _set_cell(good, 3, "time", _lines(good)[1].split(",")[0])),
        ("ragged_long", _join(lines[:mid] + [lines[mid] + ",9"] + lines[mid + 1 :])),
        ("ragged_short", _join(lines[:mid] + [lines[mid].rsplit(",", 2)[0]] + lines[mid + 1 :])),
        ("blank_line_inside", _join(lines[:mid] + [""] + lines[mid:])),
        ("unclosed_quote", _join(lines[:mid] + ['"0.1,2,3,4,5,6'] + lines[mid:])),
        ("not_utf8", good.encode()[:200] + b"\xff\xfe" + good.encode()[200:]),
        ("binary", bytes(range(256)) * 8),
        ("time_in_ms", _map_column(good, "time", lambda k, c: repr(float(c) * 1e4))),
        ("time_in_ns", _map_column(good, "time", lambda k, c: repr(float(c) * 1e-6))),
        ("lost_samples", _join(lines[:mid] + lines[mid + 40 :])),
        ("x_overflow", _set_cell(good, mid, "x", "1e308")),
        ("u_overflow", _set_cell(good, mid, "u", "-1e308")),
        (
            "all_zero",
            _map_column(
                _map_column(
                    _map_column(
                        _map_column(
                            _map_column(good, "u", lambda k, c: "0.0"), "i", lambda k, c: "0.0"
                        ),
                        "x",
                        lambda k, c: "0.0",
                    ),
                    "x_ref",
                    lambda k, c: "0.0",
                ),
                "F_load",
                lambda k, c: "0.0",
            ),
        ),
        ("constant_x", _map_column(good, "x", lambda k, c: "0.15")),
    ]
    return cases


def sidecar_cases(good: dict[str, Any]) -> list[tuple[str, str | bytes]]:
    """Bad sidecars (the CSV beside them is good): not JSON, or contradicting the CSV."""

    def with_(**kw: Any) -> str:
        d = dict(good)
        d.update(kw)
        return json.dumps(d)

    ctrl = dict(good["controller"])
    return [
        ("json_syntax", '{"schema": "feeddrive.run/1",\n "Ts": }'),
        ("json_array", "[1, 2, 3]"),
        ("json_deep", "[" * 100_000 + "]" * 100_000),
        ("json_deep_object", '{"a": ' * 50_000 + "1" + "}" * 50_000),
        ("not_utf8", b'{"name": "\xff"}'),
        ("Ts_negative", with_(Ts=-5e-4)),
        ("Ts_other", with_(Ts=1e-3)),
        ("controller_Ts_other", with_(controller=dict(ctrl, Ts=2e-3))),
        ("F_load_other", with_(F_load=54.9)),
        ("nan_literal", json.dumps(good)[:-1] + ', "force_gain": NaN}'),
    ]


def foreign_sidecar_cases(good: dict[str, Any]) -> list[tuple[str, dict[str, Any], str]]:
    """Sidecars that say something the tools do not use, with the key each note must name
    (the run stays usable: DATA.md, a sidecar is information, not a gate)."""

    def with_(**kw: Any) -> dict[str, Any]:
        d = dict(good)
        d.update(kw)
        return d

    ctrl = dict(good["controller"])
    no_schema = {k: v for k, v in good.items() if k != "schema"}
    return [
        ("controller_string", with_(controller="pid"), "controller"),
        ("controller_no_type", with_(controller={"Kp": 1.0}), "controller"),
        ("controller_unknown", with_(controller=dict(ctrl, type="fuzzy")), "'fuzzy'"),
        (
            "controller_kp_missing",
            with_(controller={k: v for k, v in ctrl.items() if k != "Kp"}),
            "'Kp' missing",
        ),
        ("controller_kp_text", with_(controller=dict(ctrl, Kp="stiff")), "Kp"),
        ("controller_kp_negative", with_(controller=dict(ctrl, Kp=-1.0)), "gains must be >= 0"),
        ("controller_law", with_(controller=dict(ctrl, law="PID, textbook")), "controller.law"),
        ("Ts_text", with_(Ts="fast"), "Ts"),
        ("sensors_string", with_(sensors="ideal"), "sensors"),
        (
            "sensors_quantum_negative",
            with_(sensors=dict(good["sensors"], quantum=-1e-7)),
            "sensors.quantum",
        ),
        (
            "sensors_unknown",
            with_(sensors=dict(good["sensors"], encoder="LIP 581")),
            "sensors.encoder",
        ),
        ("F_load_text", with_(F_load="heavy"), "F_load"),
        ("schema_other", with_(schema="other/9"), "'other/9'"),
        ("no_schema_own_keys", dict(no_schema, operator="A. N. Other"), "operator"),
        ("kind_unknown", with_(kind="banana"), None),
        ("force_gain_zero", with_(force_gain=0), "force_gain"),
    ]


def model_cases(good: dict[str, Any]) -> list[tuple[str, str | bytes]]:
    """Bad model files (JSON) made from a good model document."""

    def with_params(**kw: Any) -> str:
        d = json.loads(json.dumps(good))
        d["parameters"].update(kw)
        return json.dumps(d)

    no_effects = {k: v for k, v in good.items() if k != "effects"}
    one_missing = json.loads(json.dumps(good))
    one_missing["effects"].pop("viscous")
    text = json.dumps(good)
    return [
        ("empty", ""),
        ("json_syntax", text[: len(text) // 2]),
        ("json_array", "[]"),
        ("json_deep", "[" * 100_000 + "]" * 100_000),
        (
            "json_deep_in_parameters",
            text[:-1] + ', "extra": ' + "[" * 100_000 + "]" * 100_000 + "}",
        ),
        ("not_utf8", b'{"name": "\xff"}'),
        ("N_zero", with_params(**{"friction.N": 0})),
        ("N_eleven", with_params(**{"friction.N": 11})),
        ("N_float", with_params(**{"friction.N": 5.5})),
        ("Ts_text", with_params(Ts="fast")),
        ("Ts_zero", with_params(Ts=0.0)),
        ("m_negative", with_params(m=-16.1)),
        ("m_nan", text.replace('"m": 16.1', '"m": NaN')),
        ("m_overflow", text.replace('"m": 16.1', '"m": 1e400')),
        ("nu_sum", with_params(**{"friction.nu[1]": 0.9})),
        ("Fc_above_Fs", with_params(**{"friction.F_c": 40.0})),
        ("unknown_parameter", with_params(mass=16.1)),
        ("unknown_effect", json.dumps(dict(good, effects=dict(good["effects"], magic=True)))),
        ("missing_effects", json.dumps(no_effects)),
        ("effect_missing", json.dumps(one_missing)),
        ("effect_not_bool", json.dumps(dict(good, effects=dict(good["effects"], viscous="yes")))),
        ("parameters_list", json.dumps(dict(good, parameters=[1, 2]))),
        ("duplicate_key", text[:-1] + ', "name": "again"}'),
        ("unknown_top_key", json.dumps(dict(good, extra=1))),
        ("solver_tol_negative", with_params(**{"solver.tol": -1e-6})),
    ]
