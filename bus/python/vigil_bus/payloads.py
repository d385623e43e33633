"""ctypes structures of vigil's bus payloads (schema 2), field for field the Rust `#[repr(C)]`
layout of the `vigil-bus` crate and the C header `bus/include/vigil_bus.h`.

They are written out here (readable, with units in the names) and tested against the layout the
Rust test `bus/tests/c_layout.rs` generates (`bus/include/vigil_bus_layout.json`): same sizes,
alignments, field names, order and offsets (`bus/python/tests/test_layout.py`).

Unknown floats are NaN; unknown codes are the `*_UNKNOWN` constants (0xFF).
"""

import ctypes

SCHEMA_VERSION = 2
MAX_TARGETS = 1024
CALLSIGN_LEN = 8
ALERT_REASON_LEN = 160
DEVICE_NAME_LEN = 16
MAX_DEVICES = 8
UNIT_COUNT = 3
PAIR_COUNT = 3

# Target.address_type
ADDRESS_ICAO = 0
ADDRESS_NON_ICAO = 1
ADDRESS_TISB_OTHER = 2
ADDRESS_FLARM_RANDOM = 3
ADDRESS_FLARM_FIXED = 4
ADDRESS_SURFACE = 5
ADDRESS_UNKNOWN = 0xFF

# Target.alert_level (DO-365)
ALERT_NONE = 0
ALERT_PREVENTIVE = 1
ALERT_CORRECTIVE = 2
ALERT_WARNING = 3
ALERT_LEVEL_NAMES = {0: "none", 1: "preventive", 2: "corrective", 3: "warning"}

# Target.altitude_kind
ALTITUDE_PRESSURE = 0
ALTITUDE_GEOMETRIC = 1
ALTITUDE_UNKNOWN = 2

# Target.sources bits
SOURCE_ADSB = 1 << 0
SOURCE_UAT = 1 << 1
SOURCE_FLARM = 1 << 2
SOURCE_TISB = 1 << 3

EMITTER_UNKNOWN = 0xFF
ACCURACY_UNKNOWN = 0xFF

# AlertPayload.severity and .state
SEVERITY_ADVISORY = 0
SEVERITY_CAUTION = 1
SEVERITY_WARNING = 2
SEVERITY_NAMES = {0: "advisory", 1: "caution", 2: "warning"}
STATE_RAISED = 0
STATE_CLEARED = 1
STATE_LATCHED = 2
STATE_NAMES = {0: "raised", 1: "cleared", 2: "latched"}


def _named(name):
    """The iceoryx2 type name (the Rust `#[type_name]`), which both sides must agree on."""

    @classmethod
    def type_name(cls):
        return name

    return type_name


def _text(raw):
    """A NUL-padded text field as str (up to the first NUL or invalid UTF-8 byte)."""
    data = bytes(raw).split(b"\0", 1)[0]
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        return data[: e.start].decode("utf-8")


class Header(ctypes.Structure):
    """Common first field of every payload (32 bytes)."""

    _fields_ = [
        ("schema_version", ctypes.c_uint32),
        ("reserved", ctypes.c_uint32),
        ("seq", ctypes.c_uint64),
        ("gps_time_ns", ctypes.c_int64),
        ("send_mono_ns", ctypes.c_uint64),
    ]
    type_name = _named("vigil.Header.v1")


class UnitAttitude(ctypes.Structure):
    """One attitude unit inside AttitudePayload."""

    _fields_ = [
        ("t_gps_ns", ctypes.c_int64),
        ("roll_rad", ctypes.c_double),
        ("pitch_rad", ctypes.c_double),
        ("heading_rad", ctypes.c_double),
        ("sigma_roll_rad", ctypes.c_double),
        ("sigma_pitch_rad", ctypes.c_double),
        ("sigma_heading_rad", ctypes.c_double),
        ("valid", ctypes.c_uint8),
        ("fault_flags", ctypes.c_uint8),
        ("reserved", ctypes.c_uint8 * 6),
    ]
    type_name = _named("vigil.UnitAttitude.v1")


class AttitudePayload(ctypes.Structure):
    """`vigil/attitude`."""

    _fields_ = [
        ("header", Header),
        ("roll_rad", ctypes.c_double),
        ("pitch_rad", ctypes.c_double),
        ("heading_rad", ctypes.c_double),
        ("sigma_roll_rad", ctypes.c_double),
        ("sigma_pitch_rad", ctypes.c_double),
        ("sigma_heading_rad", ctypes.c_double),
        ("units", UnitAttitude * UNIT_COUNT),
        ("pair_verdicts", (ctypes.c_uint8 * 3) * PAIR_COUNT),
        ("isolation", ctypes.c_uint8),
        ("isolated_unit", ctypes.c_uint8),
        ("valid", ctypes.c_uint8),
        ("reserved", ctypes.c_uint8 * 4),
    ]
    type_name = _named("vigil.Attitude.v1")


class OwnshipPayload(ctypes.Structure):
    """`vigil/ownship`."""

    _fields_ = [
        ("header", Header),
        ("lat_deg", ctypes.c_double),
        ("lon_deg", ctypes.c_double),
        ("alt_pressure_m", ctypes.c_double),
        ("alt_geometric_m", ctypes.c_double),
        ("vel_north_mps", ctypes.c_double),
        ("vel_east_mps", ctypes.c_double),
        ("vel_up_mps", ctypes.c_double),
        ("ground_speed_mps", ctypes.c_double),
        ("track_deg", ctypes.c_double),
        ("sigma_horizontal_m", ctypes.c_double),
        ("sigma_vertical_m", ctypes.c_double),
        ("sigma_velocity_mps", ctypes.c_double),
        ("source", ctypes.c_uint8),
        ("valid", ctypes.c_uint8),
        ("reserved", ctypes.c_uint8 * 6),
    ]
    type_name = _named("vigil.Ownship.v1")


class Target(ctypes.Structure):
    """One target of `vigil/traffic` (an element of the slice): absolute state, accuracy and the
    relative geometry in the ownship's north-east-down frame."""

    _fields_ = [
        ("address", ctypes.c_uint32),
        ("address_type", ctypes.c_uint8),
        ("alert_level", ctypes.c_uint8),
        ("altitude_kind", ctypes.c_uint8),
        ("plausibility_flags", ctypes.c_uint8),
        ("callsign", ctypes.c_uint8 * CALLSIGN_LEN),
        ("emitter_category", ctypes.c_uint8),
        ("sources", ctypes.c_uint8),
        ("nic", ctypes.c_uint8),
        ("nac_p", ctypes.c_uint8),
        ("nac_v", ctypes.c_uint8),
        ("sil", ctypes.c_uint8),
        ("reserved", ctypes.c_uint8 * 2),
        ("flags", ctypes.c_uint32),
        ("reserved2", ctypes.c_uint32),
        ("lat_deg", ctypes.c_double),
        ("lon_deg", ctypes.c_double),
        ("alt_pressure_m", ctypes.c_double),
        ("alt_geometric_m", ctypes.c_double),
        ("track_deg", ctypes.c_double),
        ("ground_speed_mps", ctypes.c_double),
        ("vertical_rate_mps", ctypes.c_double),
        ("position_sigma_m", ctypes.c_double),
        ("age_s", ctypes.c_double),
        ("rel_north_m", ctypes.c_double),
        ("rel_east_m", ctypes.c_double),
        ("rel_down_m", ctypes.c_double),
        ("rel_vel_north_mps", ctypes.c_double),
        ("rel_vel_east_mps", ctypes.c_double),
        ("rel_vel_down_mps", ctypes.c_double),
        ("horizontal_distance_m", ctypes.c_double),
        ("vertical_separation_m", ctypes.c_double),
        ("bearing_deg", ctypes.c_double),
        ("range_rate_mps", ctypes.c_double),
        ("tcpa_s", ctypes.c_double),
        ("hmd_m", ctypes.c_double),
        ("tau_mod_s", ctypes.c_double),
        ("time_to_lowc_s", ctypes.c_double),
    ]
    type_name = _named("vigil.Target.v2")

    @property
    def address_hex(self):
        """The address as six upper-case hex digits (how every vigil output names it)."""
        return "%06X" % (self.address & 0xFFFFFF)

    @property
    def callsign_text(self):
        return _text(self.callsign)

    @property
    def alert_level_name(self):
        return ALERT_LEVEL_NAMES.get(self.alert_level, "unknown")


class TrafficHeader(ctypes.Structure):
    """User header of `vigil/traffic`: the targets follow as the sample's slice."""

    _fields_ = [
        ("header", Header),
        ("count", ctypes.c_uint32),
        ("dropped", ctypes.c_uint32),
    ]
    type_name = _named("vigil.TrafficHeader.v2")


class DeviceIntegrity(ctypes.Structure):
    """One port's entry of IntegrityPayload."""

    _fields_ = [
        ("name", ctypes.c_uint8 * DEVICE_NAME_LEN),
        ("device", ctypes.c_uint8),
        ("link_state", ctypes.c_uint8),
        ("reserved", ctypes.c_uint8 * 6),
        ("last_message_age_s", ctypes.c_double),
        ("bytes_received", ctypes.c_uint64),
        ("bytes_consumed", ctypes.c_uint64),
        ("bytes_skipped", ctypes.c_uint64),
        ("messages", ctypes.c_uint64),
        ("checksum_failures", ctypes.c_uint64),
        ("unknown_types", ctypes.c_uint64),
        ("malformed", ctypes.c_uint64),
        ("reconnects", ctypes.c_uint64),
    ]
    type_name = _named("vigil.DeviceIntegrity.v1")


class IntegrityPayload(ctypes.Structure):
    """`vigil/integrity`."""

    _fields_ = [
        ("header", Header),
        ("device_count", ctypes.c_uint32),
        ("clock_status", ctypes.c_uint8),
        ("leap_seconds_known", ctypes.c_uint8),
        ("reserved", ctypes.c_uint8 * 2),
        ("clock_offset_s", ctypes.c_double),
        ("clock_sigma_s", ctypes.c_double),
        ("devices", DeviceIntegrity * MAX_DEVICES),
    ]
    type_name = _named("vigil.Integrity.v1")


class AlertPayload(ctypes.Structure):
    """`vigil/alerts`: one alert transition."""

    _fields_ = [
        ("header", Header),
        ("alert_id", ctypes.c_uint32),
        ("severity", ctypes.c_uint8),
        ("state", ctypes.c_uint8),
        ("reserved", ctypes.c_uint8 * 2),
        ("raised_gps_ns", ctypes.c_int64),
        ("reason", ctypes.c_uint8 * ALERT_REASON_LEN),
    ]
    type_name = _named("vigil.Alert.v1")

    @property
    def reason_text(self):
        return _text(self.reason)

    @property
    def severity_name(self):
        return SEVERITY_NAMES.get(self.severity, "unknown")

    @property
    def state_name(self):
        return STATE_NAMES.get(self.state, "unknown")


#: The structs by their C name in vigil_bus.h / vigil_bus_layout.json.
BY_C_NAME = {
    "vigil_Header": Header,
    "vigil_UnitAttitude": UnitAttitude,
    "vigil_AttitudePayload": AttitudePayload,
    "vigil_OwnshipPayload": OwnshipPayload,
    "vigil_Target": Target,
    "vigil_TrafficHeader": TrafficHeader,
    "vigil_DeviceIntegrity": DeviceIntegrity,
    "vigil_IntegrityPayload": IntegrityPayload,
    "vigil_AlertPayload": AlertPayload,
}
