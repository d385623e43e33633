#!/usr/bin/env bash
# Regenerates the golden replay recordings from the scenario files next to this script
# (fixed seeds), then their golden files. Run from the repository root:
#   bash tests/data/replay/make.sh
# Only legitimate when the simulator changed on purpose (see README, "Golden replays"); review the
# diff of the .golden files before committing.
set -euo pipefail
dir=tests/data/replay
cargo build --release -q -p vigil
vigil=target/release/vigil
# Issue 24's fail-safe scenarios follow the first seven.
for scenario in nominal:20 headon:55 crossing:25 bahrs-fault:20 gnss-outage:20 link-errors:20 spoofed-target:15 \
    ownship-velocity-unknown:20 no-altitude:25 no-velocity:25 stale-reports:20 msl-only-nmea:20 \
    slow-drift-spoof:20; do
  name=${scenario%%:*}
  secs=${scenario##*:}
  "$vigil" sim --scenario "$dir/$name.toml" --duration "$secs" --seed 1 \
    --no-truth-channel --out "$dir/$name.mcap" >/dev/null
  "$vigil" replay "$dir/$name.mcap" --check "$dir/$name.golden" --bless
done
