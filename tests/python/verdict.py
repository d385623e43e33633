"""The end every CI check script shares: print the failures (the first `limit`) and exit non-zero
when there is any."""

import sys


def conclude(failures, limit=20):
    """Prints `FAIL: ...` per failure (at most `limit`) and exits 1 when `failures` is not empty."""
    if failures:
        for f in failures[:limit]:
            print("FAIL:", f)
        sys.exit(1)
