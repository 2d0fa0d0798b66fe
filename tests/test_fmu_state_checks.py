"""FMU states that carry and check every structural parameter, and a loader that checks what the
setters check (both builds of the plant, co-simulation):

* a continuous state beyond its declared range in a state whose CRC-32 was recomputed (v = 1e300)
  is refused naming v and its range, and the instance is unchanged;
* FMI 3.0: a state of another friction.N (another number of continuous states) is refused naming
  both values; a state saved in Event Mode is refused by an instance made with
  eventModeUsed = false, and loads into one made with it;
* a state of the previous format version is refused naming both versions.
"""

from __future__ import annotations

import struct
import zlib
from pathlib import Path

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi3 import FMU3Slave

from feeddrive.fmu import Plant
from feeddrive.fmu3 import configured, set_values

H = 1e-3
V0 = 0.0123456789  # m/s, a start velocity whose bytes are found in the state


def _forge(blob: bytes, old: float, new: float) -> bytes:
    """The state with the first f64 equal to ``old`` (the continuous state, which precedes the
    stored start values) replaced by ``new`` and the payload's CRC-32 recomputed (the header's
    size is its third u32, the CRC its last)."""
    b = bytearray(blob)
    at = b.index(struct.pack("<d", old))
    b[at : at + 8] = struct.pack("<d", new)
    hb = struct.unpack_from("<I", b, 8)[0]
    struct.pack_into("<I", b, hb - 4, zlib.crc32(bytes(b[hb:])) & 0xFFFFFFFF)
    return bytes(b)


@pytest.mark.parametrize("version", ["2.0", "3.0"])
def test_state_beyond_its_range_refused(fmu2_path: Path, fmu3_path: Path, version: str) -> None:
    p = Plant({}, path=fmu2_path if version == "2.0" else fmu3_path)
    p.start({"v": V0, "u": 1.0})
    blob = p.serialize_state(p.get_state())
    for k in range(20):
        p.do_step(k * H, H)
    x_before = p.get(["x"])["x"]
    n_msgs = len(p.messages)
    with pytest.raises(FMICallException):
        p.deserialize_state(_forge(blob, V0, 1e300))
    assert "state v = 1e+300 is out of range: allowed [-1000, 1000] m/s" in p.messages[-1], (
        p.messages[n_msgs:]
    )
    # refused: nothing changed, the run goes on
    assert p.get(["x"])["x"] == x_before
    p.do_step(20 * H, H)
    # in range (999 m/s), forged the same way: loads
    p.set_state(p.deserialize_state(_forge(blob, V0, 999.0)))
    assert p.get(["v"])["v"] == 999.0
    p.close()


def _cs3(path: Path, log: list[str], n: int | None = None, event_mode: bool = False) -> tuple:
    cb = {
        "logMessage": lambda env, st, cat, msg: log.append(msg.decode()),
        "eventModeUsed": event_mode,
    }
    if n is None:
        md = read_model_description(str(path))
        f = FMU3Slave(
            guid=md.guid,
            unzipDirectory=extract(str(path)),
            modelIdentifier=md.coSimulation.modelIdentifier,
            instanceName="s",
        )
        f.instantiate(**cb)
    else:
        md, f = configured(path, "CoSimulation", n, **cb)
        vr = {v.name: v.valueReference for v in md.modelVariables}
        f.setFloat64([vr["friction.nu"]], [1.0 / n] * n)
    return md, f


def test_state_of_another_friction_n_refused(fmu3_path: Path) -> None:
    """A state saved at friction.N = 5 (7 continuous states) into an instance at N = 9 (11 states):
    refused naming both N, the instance keeps its 11 states; at N = 5 it loads."""
    log: list[str] = []
    _md5, a = _cs3(fmu3_path, log)
    a.enterInitializationMode(startTime=0.0)
    a.exitInitializationMode()
    a.doStep(0.0, 0.01)
    blob = a.serializeFMUState(a.getFMUState())
    md9, b = _cs3(fmu3_path, log, n=9)
    b.enterInitializationMode(startTime=0.0)
    b.exitInitializationMode()
    with pytest.raises(FMICallException):
        b.deserializeFMUState(blob)
    assert "friction.N = 5, this instance 9" in log[-1] and "structural parameter" in log[-1], log[
        -1
    ]
    b.doStep(0.0, 0.01)  # the instance goes on, with N = 9
    vr9 = {v.name: v.valueReference for v in md9.modelVariables}
    assert len(b.getFloat64([vr9["friction.F"]], nValues=9)) == 9
    _, c = _cs3(fmu3_path, log, n=5)
    c.enterInitializationMode(startTime=0.0)
    c.exitInitializationMode()
    c.setFMUState(c.deserializeFMUState(blob))
    for f in (a, b, c):
        f.terminate()
        f.freeInstance()


def test_event_mode_state_needs_event_mode(fmu3_path: Path) -> None:
    """A state saved in Event Mode (right after initialisation with eventModeUsed) is refused by
    an instance made with eventModeUsed = false, naming the option, and loads into one made
    with it, which then runs as the original."""
    log: list[str] = []
    md, a = _cs3(fmu3_path, log, event_mode=True)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    set_values(a, md, {"u": 1.0})
    a.enterInitializationMode(startTime=0.0)
    a.exitInitializationMode()
    blob = a.serializeFMUState(a.getFMUState())
    _, plain = _cs3(fmu3_path, log)
    with pytest.raises(FMICallException):
        plain.deserializeFMUState(blob)
    assert "saved in Event Mode" in log[-1] and "eventModeUsed = false" in log[-1], log[-1]
    _, b = _cs3(fmu3_path, log, event_mode=True)
    b.setFMUState(b.deserializeFMUState(blob))
    xs = []
    for f in (a, b):
        f.updateDiscreteStates()
        f.enterStepMode()
        for k in range(50):
            f.doStep(k * H, H)
        xs.append(f.getFloat64([vr["x"]])[0])
    assert xs[0] == xs[1] and np.isfinite(xs[0])
    plain.freeInstance()
    for f in (a, b):
        f.terminate()
        f.freeInstance()


def test_previous_format_version_refused(fmu2_path: Path) -> None:
    p = Plant({}, path=fmu2_path)
    p.start({"u": 1.0})
    b = bytearray(p.serialize_state(p.get_state()))
    version = struct.unpack_from("<I", b, 4)[0]
    struct.pack_into("<I", b, 4, version - 1)
    with pytest.raises(FMICallException):
        p.deserialize_state(bytes(b))
    assert (
        f"state format version {version - 1}, this FMU reads version {version} only"
        in p.messages[-1]
    )
    p.close()
