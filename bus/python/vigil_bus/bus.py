"""Subscribing to a running vigil's services (`vigil run`, `vigil demo`, `vigil replay --publish`).

The services are `[PREFIX/]vigil/<topic>`; vigil creates them, a subscriber here only opens them
(creating one with other settings would lock vigil out), so it waits until they exist.
"""

import ctypes
import time

import iceoryx2 as iox2

from . import payloads

#: The payload structure of each topic.
TOPICS = {
    "attitude": payloads.AttitudePayload,
    "ownship": payloads.OwnshipPayload,
    "traffic": payloads.TrafficPayload,
    "integrity": payloads.IntegrityPayload,
    "alerts": payloads.AlertPayload,
}


def service_name(prefix: str, topic: str) -> str:
    """The service name of `topic` under deployment `prefix` ("" for the default names)."""
    prefix = prefix.strip("/")
    return f"{prefix}/vigil/{topic}" if prefix else f"vigil/{topic}"


class Subscriber:
    """Receives one topic's payloads as ctypes copies, and counts sequence gaps."""

    def __init__(self, node, topic: str, prefix: str = "", wait_s: float = 10.0):
        self.topic = topic
        self.payload_type = TOPICS[topic]
        name = iox2.ServiceName.new(service_name(prefix, topic))
        deadline = time.monotonic() + wait_s
        while True:
            try:
                service = node.service_builder(name).publish_subscribe(self.payload_type).open()
                break
            except Exception:  # the service does not exist yet
                if time.monotonic() > deadline:
                    raise
                time.sleep(0.02)
        self._service = service
        self._subscriber = service.subscriber_builder().create()
        self._last_seq = None
        #: Samples missed (gaps in `header.seq`) since the first one received.
        self.missed = 0

    def receive(self):
        """The next payload, copied out of shared memory, or None when none is waiting."""
        sample = self._subscriber.receive()
        if sample is None:
            return None
        data = self.payload_type.from_buffer_copy(
            ctypes.string_at(ctypes.addressof(sample.payload().contents),
                             ctypes.sizeof(self.payload_type))
        )
        seq = data.header.seq
        if self._last_seq is not None and seq > self._last_seq + 1:
            self.missed += seq - self._last_seq - 1
        self._last_seq = seq
        return data
