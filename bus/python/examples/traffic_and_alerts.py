"""Prints vigil's traffic picture and alerts: a minimal Python consumer.

    PYTHONPATH=bus/python python bus/python/examples/traffic_and_alerts.py [PREFIX]

(with `pip install iceoryx2==0.10.*`; `vigil demo` prints its prefix at start).
"""

import sys
import time

import iceoryx2 as iox2

import vigil_bus

LEVELS = ["none", "preventive", "corrective", "warning"]
STATES = ["raised", "cleared", "latched"]


def main():
    prefix = sys.argv[1] if len(sys.argv) > 1 else ""
    node = iox2.NodeBuilder.new().create(iox2.ServiceType.Ipc)
    traffic = vigil_bus.Subscriber(node, "traffic", prefix, wait_s=60.0)
    alerts = vigil_bus.Subscriber(node, "alerts", prefix, wait_s=60.0)
    while True:
        while (pic := traffic.receive()) is not None:
            for t in pic.targets:
                name = bytes(t.callsign).rstrip(b"\0").decode(errors="replace")
                print(
                    f"{t.address:06X} {name:8} {LEVELS[min(t.alert_level, 3)]:10} "
                    f"{t.lat_deg:.5f} {t.lon_deg:.5f} {t.horizontal_distance_m:.0f} m"
                )
        while (a := alerts.receive()) is not None:
            reason = bytes(a.reason).rstrip(b"\0").decode(errors="replace")
            print(f"alert {a.alert_id:08X} {STATES[min(a.state, 2)]}: {reason}")
        time.sleep(0.05)


if __name__ == "__main__":
    main()
