"""A minimal Python consumer of vigil: the traffic picture and the alerts.

    python bus/python/examples/traffic_and_alerts.py [PREFIX] [SECONDS]

next to a running `vigil run` or `vigil demo` (PREFIX: the deployment prefix it prints or its
configuration's, default none). Needs `pip install iceoryx2==0.10.*` and bus/python on the path
(`pip install bus/python` or PYTHONPATH=bus/python).
"""

import math
import sys
import time

from vigil_bus import bus


def main():
    prefix = sys.argv[1] if len(sys.argv) > 1 else ""
    seconds = float(sys.argv[2]) if len(sys.argv) > 2 else 10.0
    node = bus.node("vigil-python-example")
    traffic = bus.Subscription(node, prefix, "traffic")
    alerts = bus.Subscription(node, prefix, "alerts")
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        # Traffic is latest-state-wins: keep only the newest picture.
        latest = None
        while (p := traffic.receive()) is not None:
            latest = p
        if latest is not None:
            print(f"traffic seq {latest.header.seq}: {len(latest.targets)} targets")
            for t in latest.targets[:5]:
                lowc = "-" if math.isnan(t.time_to_lowc_s) else f"{t.time_to_lowc_s:.1f} s"
                print(
                    f"  {t.address_hex} {t.callsign_text:8} {t.alert_level_name:10} "
                    f"{t.horizontal_distance_m:8.0f} m  brg {t.bearing_deg:5.1f}  "
                    f"NED ({t.rel_north_m:.0f}, {t.rel_east_m:.0f}, {t.rel_down_m:.0f}) m  "
                    f"LoWC {lowc}"
                )
        # Alerts are events: read every one.
        while (a := alerts.receive()) is not None:
            print(f"alert {a.alert_id:#010x} {a.severity_name} {a.state_name}: {a.reason_text}")
        traffic.wait(0.1)


if __name__ == "__main__":
    main()
