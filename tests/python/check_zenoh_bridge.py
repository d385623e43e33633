"""Issue 22: two vehicles' vigil topics received by a real Zenoh client (the eclipse-zenoh package).

Two `vigil bridge` processes (vehicles uavA and uavB, each on its own bus prefix and its own
loopback endpoint) carry what two `vigil replay tests/data/replay/headon.mcap --publish --speed
10` publish. This Python peer connects to both bridges, subscribes to `vigil/*/traffic` and
`vigil/*/alerts`, and checks against the golden file (headon.golden, itself checked against the
scenario's geometry by the Rust tests): both vehicles' pictures arrive with the head-on intruder,
and each vehicle's alert transitions arrive all, in order, with no gap in their sequence numbers
(alerts are never rate-limited or dropped). It also asks `vigil/*/alerts/active` and expects an
answer from each bridge. Exits non-zero on any failure.

    python tests/python/check_zenoh_bridge.py target/debug/vigil
"""

import json
import os
import socket
import subprocess
import sys
import threading
import time

import zenoh

from verdict import conclude

GOLDEN = "tests/data/replay/headon.golden"
STATES = {"raised": 0, "cleared": 1, "latched": 2}
VEHICLES = ["uavA", "uavB"]


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def golden():
    """Traffic addresses and alert transitions (id, state code) of the golden file."""
    addresses, transitions = set(), []
    with open(GOLDEN) as f:
        for line in f:
            r = json.loads(line)
            if r.get("kind") == "traffic":
                addresses.update(int(t["address"], 16) for t in r["targets"])
            elif r.get("kind") == "alert":
                state = r["state"]
                transitions.append((r["alert_id"], STATES.get(state, state)))
    return addresses, transitions


def code(v, words):
    """A code given as a number, or as one of `words` (the JSON names)."""
    return words[v] if isinstance(v, str) else v


def address(v):
    return int(v, 16) if isinstance(v, str) else v


def main():
    vigil = sys.argv[1]
    failures = []
    pid = os.getpid()
    ports = {v: free_port() for v in VEHICLES}
    bridges = {}
    for v in VEHICLES:
        bridges[v] = subprocess.Popen(
            [vigil, "bridge", "--prefix", f"zb{pid}{v}", "--vehicle", v,
             "--listen", f"tcp/127.0.0.1:{ports[v]}"],
            stderr=subprocess.PIPE, text=True,
        )
    for v, b in bridges.items():
        line = b.stderr.readline()
        if "vigil bridge:" not in line:
            failures.append(f"bridge {v} did not start: {line!r}")
    conf = zenoh.Config()
    conf.insert_json5("mode", '"peer"')
    conf.insert_json5("connect/endpoints", json.dumps([f"tcp/127.0.0.1:{ports[v]}" for v in VEHICLES]))
    conf.insert_json5("listen/endpoints", "[]")
    conf.insert_json5("scouting/multicast/enabled", "false")
    session = zenoh.open(conf)
    lock = threading.Lock()
    got = {"traffic": [], "alerts": []}

    def keep(topic):
        def on_sample(sample):
            vehicle = str(sample.key_expr).split("/")[1]
            with lock:
                got[topic].append((vehicle, json.loads(sample.payload.to_bytes())))
        return on_sample

    subs = [session.declare_subscriber(f"vigil/*/{t}", keep(t)) for t in ("traffic", "alerts")]
    deadline = time.monotonic() + 15
    while len(list(session.info.peers_zid())) < 2 and time.monotonic() < deadline:
        time.sleep(0.05)
    if len(list(session.info.peers_zid())) < 2:
        failures.append("not connected to both bridges")
    # The subscriptions reach the bridges with the connection; give them a moment.
    time.sleep(0.5)
    replays = [
        subprocess.Popen(
            [vigil, "replay", "tests/data/replay/headon.mcap", "--publish", "--speed", "10",
             "--prefix", f"zb{pid}{v}"],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
        )
        for v in VEHICLES
    ]
    for r in replays:
        if r.wait(timeout=120) != 0:
            failures.append(f"vigil replay --publish failed: exit {r.returncode}")
    time.sleep(2.0)
    replies = list(session.get("vigil/*/alerts/active"))
    answered = sorted(str(r.ok.key_expr).split("/")[1] for r in replies if r.ok is not None)
    if answered != VEHICLES:
        failures.append(f"active-set query answered by {answered}, want {VEHICLES}")
    for s in subs:
        s.undeclare()
    session.close()
    for b in bridges.values():
        b.terminate()
    for v, b in bridges.items():
        if b.wait(timeout=10) != 0:
            failures.append(f"bridge {v} exit {b.returncode}")

    want_addresses, want_transitions = golden()
    with lock:
        traffic, alerts = list(got["traffic"]), list(got["alerts"])
    summary = []
    for v in VEHICLES:
        pics = [p for (veh, p) in traffic if veh == v]
        seen = set()
        for p in pics:
            seen.update(address(t["address"]) for t in p["targets"])
        if len(pics) < 20:
            failures.append(f"{v}: only {len(pics)} traffic pictures")
        if seen != want_addresses:
            failures.append(f"{v}: addresses {sorted(seen)}, golden {sorted(want_addresses)}")
        al = [a for (veh, a) in alerts if veh == v]
        transitions = [(a["alert_id"], code(a["state"], STATES)) for a in al]
        seqs = [a["header"]["seq"] for a in al]
        if transitions != want_transitions:
            failures.append(f"{v}: alert transitions {transitions}, golden {want_transitions}")
        if seqs != list(range(1, len(seqs) + 1)) or any(a["missed_before"] for a in al):
            failures.append(f"{v}: alert sequence {seqs}: some were lost")
        summary.append(f"{v}: {len(pics)} pictures, alerts {transitions}")
    print("Zenoh bridge:", "; ".join(summary))
    conclude(failures)


if __name__ == "__main__":
    main()
