"""Opens vigil recordings with the Python `mcap` reader and checks them (issue 20).

For each recording given:
- every channel has a schema: JSON channels a `jsonschema` one, raw port channels
  (`application/octet-stream`) a `vigil.raw.<protocol>` schema with the empty schema encoding;
- every JSON message validates against its channel's JSON Schema (`jsonschema`);
- the expected channels are there and carry messages;
- with --start-from SIM.mcap: the first log_time is within a second of the flight's UTC start,
  taken from the simulator's own metadata (`vigil.sim` start_gps_ns, GPS time, converted to UTC
  here with the 18 s of GPS - UTC since 2017), not from vigil's clock model.

Exit code 0 when every check holds; a failure names the file, the channel and the message.
"""

import argparse
import json
import sys

import jsonschema
from mcap.reader import make_reader

GPS_EPOCH_UNIX_S = 315_964_800
GPS_MINUS_UTC_S = 18  # since 2017-01-01; the simulated flights are later

FUSED = [
    "/vigil/attitude_check",
    "/vigil/ownship",
    "/vigil/ownship/fix",
    "/vigil/traffic",
    "/vigil/traffic/geojson",
    "/vigil/integrity",
]


def sim_start_unix_ns(path):
    with open(path, "rb") as f:
        for m in make_reader(f).iter_metadata():
            if m.name == "vigil.sim":
                gps_ns = int(m.metadata["start_gps_ns"])
                return gps_ns + (GPS_EPOCH_UNIX_S - GPS_MINUS_UTC_S) * 1_000_000_000
    raise SystemExit(f"{path}: no vigil.sim metadata")


def check(path, start_ns, expect, decoded):
    errors = []
    with open(path, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        if summary is None:
            return [f"{path}: no summary"]
        validators = {}
        for sid, s in summary.schemas.items():
            if s.encoding == "jsonschema":
                doc = json.loads(s.data)
                cls = jsonschema.validators.validator_for(doc)
                cls.check_schema(doc)
                validators[sid] = cls(doc)
        for ch in summary.channels.values():
            if ch.schema_id == 0 or ch.schema_id not in summary.schemas:
                errors.append(f"{path}: {ch.topic}: no schema")
                continue
            s = summary.schemas[ch.schema_id]
            if ch.message_encoding == "json":
                if s.encoding != "jsonschema":
                    errors.append(f"{path}: {ch.topic}: JSON without a JSON Schema ({s.encoding!r})")
            elif ch.message_encoding == "application/octet-stream":
                if not (s.name.startswith("vigil.raw.") and s.encoding == ""):
                    errors.append(f"{path}: {ch.topic}: raw channel schema {s.name!r}")
            else:
                errors.append(f"{path}: {ch.topic}: unexpected encoding {ch.message_encoding}")
        counts = {}
        first_log = None
        names = {}
        for schema, channel, message in reader.iter_messages(log_time_order=False):
            counts[channel.topic] = counts.get(channel.topic, 0) + 1
            names[channel.topic] = schema.name if schema else None
            first_log = message.log_time if first_log is None else min(first_log, message.log_time)
            if message.publish_time == message.log_time and start_ns is not None:
                errors.append(f"{path}: {channel.topic}: log_time is the host time")
            if channel.message_encoding != "json":
                continue
            try:
                doc = json.loads(message.data)
            except ValueError as e:
                errors.append(f"{path}: {channel.topic} #{counts[channel.topic]}: not JSON: {e}")
                continue
            for e in validators[channel.schema_id].iter_errors(doc):
                errors.append(
                    f"{path}: {channel.topic} #{counts[channel.topic]}: {e.message} at {list(e.path)}"
                )
                break
            if len(errors) > 20:
                return errors
    wanted = list(expect)
    if decoded:
        wanted += ["/vn200/decoded", "/bahrs/decoded"]
    for topic in wanted:
        if counts.get(topic, 0) == 0:
            errors.append(f"{path}: no message on {topic}")
    for topic, name in [
        ("/vigil/ownship/fix", "foxglove.LocationFix"),
        ("/vigil/traffic/geojson", "foxglove.GeoJSON"),
        ("/vigil/alerts/log", "foxglove.Log"),
    ]:
        if topic in names and names[topic] != name:
            errors.append(f"{path}: {topic} has schema {names[topic]}, not {name}")
    if start_ns is not None and first_log is not None:
        off = (first_log - start_ns) / 1e9
        print(f"{path}: first log_time {off:+.3f} s from the flight's UTC start")
        if abs(off) > 1.0:
            errors.append(f"{path}: first log_time {off:+.3f} s from the flight's UTC start")
    print(f"{path}: {sum(counts.values())} messages on {len(counts)} channels checked")
    return errors


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("recording")
    p.add_argument("--start-from", help="simulator recording whose vigil.sim metadata gives the start")
    p.add_argument("--alerts", action="store_true", help="expect messages on /vigil/alerts")
    p.add_argument("--decoded", action="store_true", help="expect decoded channels")
    a = p.parse_args()
    start = sim_start_unix_ns(a.start_from) if a.start_from else None
    expect = FUSED + (["/vigil/alerts", "/vigil/alerts/log"] if a.alerts else [])
    errors = check(a.recording, start, expect, a.decoded)
    for e in errors:
        print("FAIL", e, file=sys.stderr)
    sys.exit(1 if errors else 0)


if __name__ == "__main__":
    main()
