"""Subscribing to a running vigil's services (`vigil run`, `vigil demo`, `vigil replay --publish`).

The services are `[PREFIX/]vigil/<topic>`; vigil creates them, a subscriber here only opens them
(creating one with other settings would lock vigil out), so it waits until they exist.

Every topic but traffic carries one fixed-size structure. Traffic (schema 3) is a slice service:
the sample's payload is `count` `Target`s and its iceoryx2 user header a `TrafficHeader`; a
received picture comes back as a `TrafficPicture`.
"""

import ctypes
import time
from dataclasses import dataclass, field

import iceoryx2 as iox2

from . import payloads

#: The payload structure of each topic (for traffic: one element of its slice).
TOPICS = {
    "attitude": payloads.AttitudePayload,
    "ownship": payloads.OwnshipPayload,
    "traffic": payloads.Target,
    "integrity": payloads.IntegrityPayload,
    "alerts": payloads.AlertPayload,
}


@dataclass
class TrafficPicture:
    """One traffic sample copied out of shared memory: the header's fields and the targets."""

    header: payloads.Header
    count: int
    dropped: int
    targets: list = field(default_factory=list)


def service_name(prefix: str, topic: str) -> str:
    """The service name of `topic` under deployment `prefix` ("" for the default names)."""
    prefix = prefix.strip("/")
    return f"{prefix}/vigil/{topic}" if prefix else f"vigil/{topic}"


def _copy(cls, address):
    """A ctypes copy of the `cls` structure at `address`."""
    return cls.from_buffer_copy(ctypes.string_at(address, ctypes.sizeof(cls)))


class Subscriber:
    """Receives one topic's payloads as ctypes copies, and counts sequence gaps."""

    def __init__(self, node, topic: str, prefix: str = "", wait_s: float = 10.0):
        self.topic = topic
        self.payload_type = TOPICS[topic]
        name = iox2.ServiceName.new(service_name(prefix, topic))
        deadline = time.monotonic() + wait_s
        while True:
            try:
                builder = node.service_builder(name)
                if topic == "traffic":
                    builder = builder.publish_subscribe(iox2.Slice[payloads.Target]).user_header(
                        payloads.TrafficHeader
                    )
                else:
                    builder = builder.publish_subscribe(self.payload_type)
                service = builder.open()
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
        """The next payload copied out of shared memory (a `TrafficPicture` for traffic), or
        None when none is waiting."""
        sample = self._subscriber.receive()
        if sample is None:
            return None
        if self.topic == "traffic":
            h = _copy(payloads.TrafficHeader, ctypes.addressof(sample.user_header().contents))
            targets = sample.payload()
            # The header's count, never beyond the slice (a bad count must not read past it).
            n = min(h.count, targets.len())
            size = ctypes.sizeof(payloads.Target)
            data = TrafficPicture(
                header=h.header,
                count=n,
                dropped=h.dropped,
                targets=[_copy(payloads.Target, targets.as_ptr() + i * size) for i in range(n)],
            )
        else:
            data = _copy(self.payload_type, ctypes.addressof(sample.payload().contents))
        seq = data.header.seq
        if self._last_seq is not None and seq > self._last_seq + 1:
            self.missed += seq - self._last_seq - 1
        self._last_seq = seq
        return data
