"""vigil's bus for Python: the payload structures (ctypes, schema 2) and subscribers over the
`iceoryx2` package. See `bus/python/README.md`."""

from .payloads import *  # noqa: F401,F403
from .payloads import BY_C_NAME, SCHEMA_VERSION  # noqa: F401

try:  # The structures are usable without iceoryx2 (e.g. to parse a recording).
    from .bus import Subscription, TrafficPicture, node, service_name  # noqa: F401
except ImportError:  # pragma: no cover
    pass
