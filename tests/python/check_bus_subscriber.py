"""Issue 26: vigil's payloads received in Python through the iceoryx2 package.

1. The ctypes structures (bus/python/vigil_bus/payloads.py, generated from the Rust layout) lay
   out exactly as Rust does: ctypes computes every size, alignment and field offset itself and
   they are compared with the Rust figures recorded next to them.
2. `vigil replay tests/data/replay/headon.mcap --publish --speed 10` publishes the golden head-on
   flight; this subscriber receives traffic and alerts and checks them against the golden file
   (`headon.golden`, checked against the scenario's geometry by the Rust tests): every traffic
   address it lists, the highest alert level it gives each, schema version 3, sequence numbers
   only increasing, each picture's slice as long as its count, and the same alert transitions (id and state) in the same order. Exits
   non-zero on any failure.
"""

import ctypes
import json
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "bus", "python"))

import iceoryx2 as iox2  # noqa: E402

import vigil_bus  # noqa: E402
from vigil_bus import payloads  # noqa: E402
from verdict import conclude  # noqa: E402


def check_layout(failures):
    for name, (size, align, fields) in payloads.LAYOUT.items():
        cls = getattr(payloads, name)
        if ctypes.sizeof(cls) != size:
            failures.append(f"{name}: ctypes size {ctypes.sizeof(cls)}, Rust {size}")
        if ctypes.alignment(cls) != align:
            failures.append(f"{name}: ctypes alignment {ctypes.alignment(cls)}, Rust {align}")
        for field, (offset, fsize) in fields.items():
            d = getattr(cls, field)
            if (d.offset, d.size) != (offset, fsize):
                failures.append(f"{name}.{field}: ctypes ({d.offset}, {d.size}), Rust ({offset}, {fsize})")


GOLDEN = "tests/data/replay/headon.golden"
STATES = {"raised": 0, "cleared": 1, "latched": 2}
LEVELS = {"none": 0, "preventive": 1, "corrective": 2, "warning": 3}


def golden():
    """Per address the highest alert level, and the alert transitions, from the golden file."""
    levels, transitions = {}, []
    with open(GOLDEN) as f:
        for line in f:
            r = json.loads(line)
            if r.get("kind") == "traffic":
                for t in r["targets"]:
                    a = int(t["address"], 16)
                    lvl = t["alert_level"]
                    lvl = LEVELS[lvl] if isinstance(lvl, str) else lvl
                    levels[a] = max(levels.get(a, 0), lvl)
            elif r.get("kind") == "alert":
                transitions.append((r["alert_id"], STATES[r["state"]]))
    return levels, transitions


def main():
    vigil = sys.argv[1]
    failures = []
    check_layout(failures)
    prefix = f"py{os.getpid()}"
    replay = subprocess.Popen(
        [vigil, "replay", "tests/data/replay/headon.mcap", "--publish", "--speed", "10",
         "--prefix", prefix],
        stdout=subprocess.DEVNULL,
    )
    node = iox2.NodeBuilder.new().create(iox2.ServiceType.Ipc)
    traffic = vigil_bus.Subscriber(node, "traffic", prefix)
    alerts = vigil_bus.Subscriber(node, "alerts", prefix)
    want_levels, want_transitions = golden()
    pictures, seqs, levels, transitions = 0, [], {}, []
    end = None
    while end is None or time.monotonic() < end:
        if end is None and replay.poll() is not None:
            end = time.monotonic() + 1.0
        while (pic := traffic.receive()) is not None:
            pictures += 1
            seqs.append(pic.header.seq)
            if pic.header.schema_version != 3:
                failures.append(f"schema version {pic.header.schema_version}")
            if len(pic.targets) != pic.count:
                failures.append(f"picture {pic.header.seq}: {len(pic.targets)} targets, count {pic.count}")
            for t in pic.targets:
                levels[t.address] = max(levels.get(t.address, 0), t.alert_level)
        while (a := alerts.receive()) is not None:
            transitions.append((a.alert_id, a.state))
        time.sleep(0.01)
    if replay.returncode != 0:
        failures.append(f"vigil replay --publish failed: exit {replay.returncode}")
    if pictures < 20:
        failures.append(f"only {pictures} traffic pictures")
    if any(b <= a for a, b in zip(seqs, seqs[1:])):
        failures.append("traffic sequence numbers not increasing")
    if levels != want_levels:
        failures.append(f"addresses and highest alert levels {levels}, golden {want_levels}")
    if transitions != want_transitions:
        failures.append(f"alert transitions {transitions}, golden {want_transitions}")
    print(
        f"Python subscriber: layout of {len(payloads.LAYOUT)} structures checked; "
        f"{pictures} traffic pictures ({traffic.missed} missed); targets and highest levels "
        f"{ {f'{a:06X}': l for a, l in levels.items()} }; alert transitions {transitions}"
    )
    conclude(failures)


if __name__ == "__main__":
    main()
