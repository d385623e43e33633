"""Issue 26: vigil's MAVLink traffic output, received by a real MAVLink client (pymavlink).

Runs `vigil demo --mavlink-out 127.0.0.1:PORT --record REC` while pymavlink listens on PORT,
then checks every ADSB_VEHICLE received for the demo's head-on intruder against the fused
traffic picture recorded in the same run (the `/vigil/traffic` channel of REC): ICAO address and
callsign equal, position within 50 m, altitude within 25 ft. The k-th message for the target
belongs to the k-th recorded picture holding it (one picture per GPS second, and a target is
sent at most, and here exactly, once per second). Also checks the HEARTBEAT (MAV_TYPE_ADSB, one
a second) and the rate limit. Exits non-zero on any failure.
"""

import argparse
import json
import math
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from mcap.reader import make_reader
from pymavlink import mavutil
from verdict import conclude

FT = 0.3048


def distance_m(lat1, lon1, lat2, lon2):
    """Great-circle distance on a 6371 km sphere (enough at 50 m)."""
    p1, p2 = math.radians(lat1), math.radians(lat2)
    dp, dl = p2 - p1, math.radians(lon2 - lon1)
    a = math.sin(dp / 2) ** 2 + math.cos(p1) * math.cos(p2) * math.sin(dl / 2) ** 2
    return 2 * 6371e3 * math.asin(math.sqrt(a))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--vigil", required=True, help="the vigil binary")
    ap.add_argument("--port", type=int, default=14557)
    ap.add_argument("--icao", default="4B1A09", help="the demo's head-on intruder")
    ap.add_argument("--callsign", default="HEADON9")
    ap.add_argument("--duration", type=float, default=25.0)
    args = ap.parse_args()

    conn = mavutil.mavlink_connection(f"udpin:127.0.0.1:{args.port}")
    received, heartbeats, others = [], [], 0
    with tempfile.TemporaryDirectory() as tmp:
        rec = Path(tmp) / "mavlink.mcap"
        demo = subprocess.Popen(
            [args.vigil, "demo", "--duration", str(args.duration), "--seed", "1",
             "--record", str(rec), "--record-channels", "raw+fused",
             "--mavlink-out", f"127.0.0.1:{args.port}"],
            stdout=subprocess.DEVNULL,
        )
        deadline = time.monotonic() + args.duration + 60
        while True:
            m = conn.recv_match(type=["ADSB_VEHICLE", "HEARTBEAT"], blocking=True, timeout=0.5)
            if m is not None:
                if m.get_type() == "HEARTBEAT":
                    heartbeats.append(m)
                elif m.ICAO_address == int(args.icao, 16):
                    received.append(m)
                else:
                    others += 1
            elif demo.poll() is not None:
                break
            if time.monotonic() > deadline:
                demo.kill()
                sys.exit("the demo did not end")
        if demo.returncode != 0:
            sys.exit(f"vigil demo failed: exit {demo.returncode}")

        fused = []
        with open(rec, "rb") as f:
            for _, _, msg in make_reader(f).iter_messages(topics=["/vigil/traffic"]):
                pic = json.loads(msg.data)
                for t in pic["targets"]:
                    if t["address"] == args.icao:
                        fused.append(t)

    failures = []
    if len(received) < args.duration / 2:
        failures.append(f"only {len(received)} ADSB_VEHICLE for {args.icao}")
    # The output and the recorder see the same pictures; the last one may miss either.
    if abs(len(received) - len(fused)) > 1:
        failures.append(f"{len(received)} messages but {len(fused)} recorded pictures")
    worst_pos, worst_alt = 0.0, 0.0
    for k, (m, t) in enumerate(zip(received, fused)):
        d = distance_m(m.lat / 1e7, m.lon / 1e7, t["lat_deg"], t["lon_deg"])
        worst_pos = max(worst_pos, d)
        if d > 50.0:
            failures.append(f"message {k}: {d:.1f} m from the fused position")
        if t["alt_m"] is None:
            if m.flags & 2:
                failures.append(f"message {k}: altitude flagged valid, fused has none")
            continue
        dz = abs(m.altitude / 1000.0 - t["alt_m"])
        worst_alt = max(worst_alt, dz)
        if dz > 25 * FT:
            failures.append(f"message {k}: altitude {dz / FT:.1f} ft from the fused one")
        kind = {"pressure": 0, "geometric": 1}.get(t["altitude_kind"])
        if kind is not None and m.altitude_type != kind:
            failures.append(f"message {k}: altitude_type {m.altitude_type}, fused {kind}")
        callsign = m.callsign.decode() if isinstance(m.callsign, bytes) else m.callsign
        if callsign.rstrip("\x00 ") != args.callsign:
            failures.append(f"message {k}: callsign {callsign!r}")
    if len(heartbeats) < args.duration / 2:
        failures.append(f"only {len(heartbeats)} heartbeats")
    if heartbeats and heartbeats[0].type != mavutil.mavlink.MAV_TYPE_ADSB:
        failures.append(f"heartbeat type {heartbeats[0].type}, not MAV_TYPE_ADSB")
    # At most once a second per target: no more messages than seconds of demo (plus start-up).
    if len(received) > args.duration + 15:
        failures.append(f"{len(received)} messages in a {args.duration} s demo: rate limit broken")

    print(
        f"MAVLink: {len(received)} ADSB_VEHICLE for {args.icao} ({len(fused)} fused pictures), "
        f"{others} for other targets, {len(heartbeats)} heartbeats; worst position error "
        f"{worst_pos:.2f} m, altitude {worst_alt / FT:.2f} ft"
    )
    conclude(failures)


if __name__ == "__main__":
    main()
