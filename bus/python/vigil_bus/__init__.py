"""vigil's bus for Python: the payloads (ctypes, generated from the Rust layout) and a small
subscriber over the iceoryx2 Python package (`pip install iceoryx2==0.10.*`)."""

from .bus import TOPICS, Subscriber, TrafficPicture, service_name
from .payloads import *  # noqa: F401,F403  (every payload structure)
