"""The Python subscriber against a real publisher: `vigil replay --publish --speed max` sends the
head-on golden recording on the bus (lossless mode) and this test receives it with the
`iceoryx2` package and the ctypes structures, then checks it against the golden file written by
the Rust replay (tests/data/replay/headon.golden): every picture, in sequence, with the golden's
addresses and alert levels, and the monitor's traffic alert for the intruder."""

import json
import os
import pathlib
import subprocess
import time

from vigil_bus import bus, payloads

REPO = pathlib.Path(__file__).resolve().parents[3]
REPLAY = REPO / "tests" / "data" / "replay"


def vigil_binary():
    path = os.environ.get("VIGIL_BIN") or str(REPO / "target" / "debug" / "vigil")
    assert os.path.exists(path), f"build vigil first (cargo build -p vigil): {path}"
    return path


def golden_traffic(name):
    """t_gps_ns -> [(address, alert_level)] of the golden's traffic lines."""
    out = {}
    for line in (REPLAY / f"{name}.golden").read_text().splitlines():
        rec = json.loads(line)
        if rec.get("kind") == "traffic":
            out[rec["t_gps_ns"]] = [(t["address"], t["alert_level"]) for t in rec["targets"]]
    return out


def receive_replay(name, prefix):
    node = bus.node("vigil-pytest")
    # Subscribe first (the lossless mode of --speed max), then start the publisher.
    traffic = bus.Subscription(node, prefix, "traffic", lossless=True)
    alerts = bus.Subscription(node, prefix, "alerts", lossless=True)
    replay = subprocess.Popen(
        [vigil_binary(), "replay", str(REPLAY / f"{name}.mcap"), "--publish", "--speed", "max",
         "--prefix", prefix],
        stdout=subprocess.DEVNULL,
    )
    pictures, transitions = [], []
    deadline = time.monotonic() + 120
    while True:
        done = replay.poll() is not None
        for sub, out in ((traffic, pictures), (alerts, transitions)):
            while (x := sub.receive()) is not None:
                out.append(x)
        if done or time.monotonic() > deadline:
            break
        traffic.wait(0.02)
    replay.wait(timeout=10)
    assert replay.returncode == 0
    return pictures, transitions, traffic, alerts


def test_replayed_headon_arrives_whole_with_the_golden_addresses_and_alert_levels():
    golden = golden_traffic("headon")
    pictures, transitions, traffic, alerts = receive_replay(
        "headon", f"vigil-pytest-{os.getpid()}"
    )
    # Sequence numbers: 1, 2, ... with no gap, nothing missed (lossless mode).
    assert [p.header.seq for p in pictures] == list(range(1, len(pictures) + 1))
    assert traffic.missed == 0 and alerts.missed == 0
    assert all(p.header.schema_version == payloads.SCHEMA_VERSION for p in pictures)
    # Every golden picture arrived, with the same targets in the same order.
    by_time = {p.header.gps_time_ns: p for p in pictures}
    assert set(golden) <= set(by_time), sorted(set(golden) - set(by_time))
    for t, expected in golden.items():
        p = by_time[t]
        got = [(x.address_hex, x.alert_level) for x in p.targets]
        assert got == expected, (t, got, expected)
        assert p.count == len(p.targets) and p.dropped == 0
    # The head-on intruder reaches the warning level in the golden, so the monitor raises its
    # traffic alert: id 0x20 (TrafficAlert, ICAO) << 24 | address, severity warning.
    assert max(level for ts in golden.values() for _, level in ts) == payloads.ALERT_WARNING
    raised = [a for a in transitions if a.state == payloads.STATE_RAISED]
    ids = {a.alert_id: a for a in raised}
    assert 0x204B1A01 in ids, [hex(a.alert_id) for a in raised]
    assert ids[0x204B1A01].severity_name == "warning"
    assert [a.header.seq for a in transitions] == list(range(1, len(transitions) + 1))
