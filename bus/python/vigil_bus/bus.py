"""Subscribing to vigil's services with the `iceoryx2` Python package (0.10).

The services are opened with the same settings `vigil-bus` uses (`bus/src/policy.rs`), so a
Python subscriber may start before or after the vigil publisher. `lossless=True` is the mode of
`vigil replay --publish --speed max` (every sample delivered, the publisher waits for a full
buffer); a subscriber must use the mode its publisher uses.
"""

import ctypes
import time

import iceoryx2 as iox2

from .payloads import (
    AlertPayload,
    AttitudePayload,
    IntegrityPayload,
    OwnshipPayload,
    Target,
    TrafficHeader,
)

#: Smallest subscriber buffer of the lossless mode (vigil_bus::LOSSLESS_BUFFER).
LOSSLESS_BUFFER = 64

#: topic -> (payload type, latest-state-wins, buffer, history, max borrowed, max subscribers,
#: max publishers, max nodes): a copy of bus/src/policy.rs.
POLICIES = {
    "attitude": (AttitudePayload, True, 8, 1, 2, 16, 1, 24),
    "ownship": (OwnshipPayload, True, 8, 1, 2, 16, 1, 24),
    "traffic": (iox2.Slice[Target], True, 2, 1, 2, 8, 1, 16),
    "integrity": (IntegrityPayload, True, 8, 1, 2, 16, 1, 24),
    "alerts": (AlertPayload, False, 256, 16, 4, 16, 4, 24),
}


def service_name(prefix, topic):
    """`[PREFIX/]vigil/TOPIC`, as vigil_bus::service_name."""
    return f"{prefix}/vigil/{topic}" if prefix else f"vigil/{topic}"


class Subscription:
    """A subscriber of one topic with its wake-up listener and sequence-gap count."""

    def __init__(self, node, prefix, topic, lossless=False):
        payload, latest, buf, hist, borrowed, subs, pubs, nodes = POLICIES[topic]
        if lossless:
            buf = max(buf, LOSSLESS_BUFFER)
        self.topic = topic
        builder = node.service_builder(
            iox2.ServiceName.new(service_name(prefix, topic))
        ).publish_subscribe(payload)
        if topic == "traffic":
            builder = builder.user_header(TrafficHeader)
        self._service = (
            builder.enable_safe_overflow(latest and not lossless)
            .subscriber_max_buffer_size(buf)
            .history_size(hist)
            .subscriber_max_borrowed_samples(borrowed)
            .max_subscribers(subs)
            .max_publishers(pubs)
            .max_nodes(nodes)
            .open_or_create()
        )
        self._sub = self._service.subscriber_builder().buffer_size(buf).create()
        self._event = (
            node.service_builder(
                iox2.ServiceName.new(service_name(prefix, topic) + "/event")
            )
            .event()
            .max_notifiers(pubs)
            .max_listeners(subs)
            .max_nodes(nodes)
            .open_or_create()
        )
        self._listener = self._event.listener_builder().create()
        self.last_seq = None
        self.missed = 0

    def wait(self, timeout_s):
        """Sleeps until the publisher's wake-up or the timeout."""
        self._listener.timed_wait(iox2.Duration.from_secs_f64(timeout_s))

    def receive(self):
        """The next sample copied out of shared memory, or None: a `TrafficPicture` for
        traffic, the payload structure otherwise. Counts sequence gaps in `missed`."""
        sample = self._sub.receive()
        if sample is None:
            return None
        if self.topic == "traffic":
            head = _copy(sample.user_header().contents)
            targets = sample.payload()
            # The count is trusted only up to the slice's length.
            n = min(head.count, targets.len())
            value = TrafficPicture(head, [_copy(targets[i]) for i in range(n)])
            seq = head.header.seq
        else:
            value = _copy(sample.payload().contents)
            seq = value.header.seq
        # Hands the slot back to the publisher at once (a subscriber may borrow only a few).
        sample.delete()
        if self.last_seq is not None and seq > self.last_seq + 1:
            self.missed += seq - self.last_seq - 1
        self.last_seq = seq
        return value


def _copy(obj):
    """A copy of a ctypes structure out of shared memory."""
    new = type(obj)()
    ctypes.memmove(ctypes.byref(new), ctypes.byref(obj), ctypes.sizeof(obj))
    return new


class TrafficPicture:
    """A received traffic picture: the wire header and the targets (most urgent first)."""

    def __init__(self, head, targets):
        self.header = head.header
        self.count = head.count
        self.dropped = head.dropped
        self.targets = targets


def node(name="vigil-python"):
    """An iceoryx2 node for the subscriptions (handles no signals)."""
    return iox2.NodeBuilder.new().name(iox2.NodeName.new(name)).create(iox2.ServiceType.Ipc)


def wait_any(subscriptions, timeout_s):
    """Waits on the first subscription's wake-up (a bounded poll of the others)."""
    if subscriptions:
        subscriptions[0].wait(timeout_s)
    else:
        time.sleep(timeout_s)


__all__ = ["Subscription", "TrafficPicture", "node", "service_name", "wait_any"]
