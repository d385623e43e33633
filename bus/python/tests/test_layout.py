"""The ctypes structures against the Rust layout: sizes, alignments, field names, order, offsets
and sizes from bus/include/vigil_bus_layout.json (written by the Rust test c_layout from
offset_of!/size_of), and the constants against the C header's #defines (cbindgen)."""

import ctypes
import json
import pathlib
import re

from vigil_bus import payloads

INCLUDE = pathlib.Path(__file__).resolve().parents[2] / "include"


def test_structs_match_the_rust_layout():
    spec = json.loads((INCLUDE / "vigil_bus_layout.json").read_text())
    assert spec["schema_version"] == payloads.SCHEMA_VERSION
    assert spec["max_targets"] == payloads.MAX_TARGETS
    assert set(spec["structs"]) == set(payloads.BY_C_NAME)
    for name, s in spec["structs"].items():
        cls = payloads.BY_C_NAME[name]
        assert ctypes.sizeof(cls) == s["size"], name
        assert ctypes.alignment(cls) == s["align"], name
        assert [f[0] for f in cls._fields_] == [f["name"] for f in s["fields"]], name
        for f in s["fields"]:
            d = getattr(cls, f["name"])
            assert (d.offset, d.size) == (f["offset"], f["size"]), (name, f)


def test_constants_match_the_c_header():
    header = (INCLUDE / "vigil_bus.h").read_text()
    defines = dict(re.findall(r"#define vigil_(\w+) (\d+|\(1 << \d+\))\n", header))
    checked = 0
    for name, value in defines.items():
        if hasattr(payloads, name):
            assert getattr(payloads, name) == eval(value), name  # noqa: S307 (digits, shifts)
            checked += 1
    # Every code the package defines is in the header.
    assert checked >= 30, checked


def test_type_names_are_the_rust_ones():
    assert payloads.Target.type_name() == "vigil.Target.v2"
    assert payloads.TrafficHeader.type_name() == "vigil.TrafficHeader.v2"
    assert payloads.AlertPayload.type_name() == "vigil.Alert.v1"
