//! One name per quantity in vigil's JSON output (issue 26, point 6): the normaliser that
//! `vigil decode`, `vigil listen`, `vigil replay` (decoded, aligned and fused lines, golden files)
//! and `vigil geometry` apply to each line's `serde_json::Value` before printing it.
//!
//! Key-based and recursive (any depth, arrays included):
//! - an integer under an address key ([`ADDRESS_KEYS`]) becomes six upper-case hex digits
//!   (`"4B1A01"`): the 24-bit ICAO (or other) address as every aviation tool writes it;
//! - an integer code of the bus payloads with named constants (alert level, severity, alert state,
//!   address type, altitude kind, ownship source, device, link state, clock status, attitude
//!   verdicts, coverage, isolation, health) becomes its word, from [`code_word`]: one table per
//!   concept, the words taken from the constants' names in `vigil_bus::payload`. A code without a
//!   constant stays a number (never a guess). Bit sets (`flags`, `plausibility_flags`,
//!   `fault_flags`, `clock_disagreement`) stay numbers: they are not one code;
//! - every GPS time in ns (`gps_time_ns`, `t_gps_ns`, any `*_gps_ns`) gets a sibling with the same
//!   stem and `_utc` (`t_gps_ns` -> `t_utc`, `raised_gps_ns` -> `raised_utc`, `gps_time_ns` ->
//!   `time_utc`): ISO 8601 UTC with milliseconds and `Z` (`2016-05-31T10:00:01.250Z`), converted
//!   with the leap-second table of `vigil_fusion::time::gps`; a time of 0 (vigil's "no time yet")
//!   or null gives null;
//! - the loss-of-well-clear names are made one: `time_to_loss_of_well_clear_s` ->
//!   `time_to_lowc_s` (the payload's name, s until the loss of well clear begins) and
//!   `loss_of_well_clear_interval_s` -> `lowc_interval_s` (the interval [start, end], s: a
//!   different quantity, so a different name).

use serde_json::{Map, Value};
use vigil_bus::payload::{alerts, attitude, integrity, ownship, traffic};
use vigil_fusion::time::gps::{
    GPS_EPOCH_UNIX_S, NS_PER_S, S_PER_DAY, civil_from_days, gps_minus_utc_s,
};

/// Keys whose integer values are 24-bit addresses, written as six upper-case hex digits.
pub const ADDRESS_KEYS: [&str; 4] = ["address", "icao", "icao_address", "target_address"];

/// Keys renamed so one quantity has one name (old, new).
const RENAMES: [(&str, &str); 2] = [
    ("time_to_loss_of_well_clear_s", "time_to_lowc_s"),
    ("loss_of_well_clear_interval_s", "lowc_interval_s"),
];

/// The concepts whose integer codes have words.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Code {
    /// DAA alert level (`traffic::ALERT_*`).
    AlertLevel,
    /// Alert severity (`alerts::SEVERITY_*`).
    Severity,
    /// Alert state (`alerts::STATE_*`).
    AlertState,
    /// Traffic address type (`traffic::ADDRESS_*`).
    AddressType,
    /// Traffic altitude kind (`traffic::ALTITUDE_*`).
    AltitudeKind,
    /// Ownship solution source (`ownship::SOURCE_*`).
    OwnshipSource,
    /// Device (`integrity::DEVICE_*`).
    Device,
    /// Link state (`integrity::LINK_*`).
    LinkState,
    /// Clock status (`integrity::CLOCK_*`).
    ClockStatus,
    /// Attitude unit (`attitude::UNIT_*`).
    Unit,
    /// Pairwise verdict (`attitude::VERDICT_*`).
    Verdict,
    /// Isolation outcome (`attitude::ISOLATION_*`).
    Isolation,
    /// Comparison coverage (`attitude::COVERAGE_*`).
    Coverage,
    /// BAHRS signal health (`attitude::HEALTH_*`).
    BahrsHealth,
    /// Health comparison state (`integrity::HEALTH_AGREE` ...).
    HealthState,
    /// Why a health combination was not compared (`integrity::HEALTH_WHY_*`).
    HealthWhy,
}

/// The word of an integer code, or `None` when the code has no named constant (it then stays a
/// number).
pub fn code_word(code: Code, value: u64) -> Option<&'static str> {
    let v = u8::try_from(value).ok()?;
    let w = match code {
        Code::AlertLevel => match v {
            traffic::ALERT_NONE => "none",
            traffic::ALERT_PREVENTIVE => "preventive",
            traffic::ALERT_CORRECTIVE => "corrective",
            traffic::ALERT_WARNING => "warning",
            _ => return None,
        },
        Code::Severity => match v {
            alerts::SEVERITY_ADVISORY => "advisory",
            alerts::SEVERITY_CAUTION => "caution",
            alerts::SEVERITY_WARNING => "warning",
            _ => return None,
        },
        Code::AlertState => match v {
            alerts::STATE_RAISED => "raised",
            alerts::STATE_CLEARED => "cleared",
            alerts::STATE_LATCHED => "latched",
            _ => return None,
        },
        Code::AddressType => match v {
            traffic::ADDRESS_ICAO => "icao",
            traffic::ADDRESS_NON_ICAO => "non_icao",
            traffic::ADDRESS_TISB_OTHER => "tisb_other",
            traffic::ADDRESS_FLARM_RANDOM => "flarm_random",
            traffic::ADDRESS_FLARM_FIXED => "flarm_fixed",
            traffic::ADDRESS_SURFACE => "surface",
            traffic::ADDRESS_UNKNOWN => "unknown",
            _ => return None,
        },
        Code::AltitudeKind => match v {
            traffic::ALTITUDE_PRESSURE => "pressure",
            traffic::ALTITUDE_GEOMETRIC => "geometric",
            traffic::ALTITUDE_UNKNOWN => "unknown",
            _ => return None,
        },
        Code::OwnshipSource => match v {
            ownship::SOURCE_NONE => "none",
            ownship::SOURCE_VN200_INS => "vn200_ins",
            ownship::SOURCE_TTMRF_GNSS => "ttmrf_gnss",
            ownship::SOURCE_EXTERNAL => "external",
            _ => return None,
        },
        Code::Device => match v {
            integrity::DEVICE_BAHRS => "bahrs",
            integrity::DEVICE_VN200 => "vn200",
            integrity::DEVICE_WATSON => "watson",
            integrity::DEVICE_TTMRF => "ttmrf",
            integrity::DEVICE_OTHER => "other",
            _ => return None,
        },
        Code::LinkState => match v {
            integrity::LINK_UNKNOWN => "unknown",
            integrity::LINK_OK => "ok",
            integrity::LINK_SILENT => "silent",
            integrity::LINK_DISCONNECTED => "disconnected",
            _ => return None,
        },
        Code::ClockStatus => match v {
            integrity::CLOCK_NOT_LOCKED => "not_locked",
            integrity::CLOCK_GPS_TIME => "gps_time",
            integrity::CLOCK_PPS_LOCKED => "pps_locked",
            integrity::CLOCK_HOLDOVER => "holdover",
            _ => return None,
        },
        Code::Unit => match v {
            attitude::UNIT_BAHRS => "bahrs",
            attitude::UNIT_VN200 => "vn200",
            attitude::UNIT_WATSON => "watson",
            attitude::UNIT_NONE => "none",
            _ => return None,
        },
        Code::Verdict => match v {
            attitude::VERDICT_PASS => "pass",
            attitude::VERDICT_FAIL => "fail",
            attitude::VERDICT_NOT_COMPARED => "not_compared",
            _ => return None,
        },
        Code::Isolation => match v {
            attitude::ISOLATION_NO_FAULT => "no_fault",
            attitude::ISOLATION_NOT_COMPARED => "not_compared",
            attitude::ISOLATION_DETECTED_NOT_ISOLATED => "detected_not_isolated",
            attitude::ISOLATION_ISOLATED => "isolated",
            _ => return None,
        },
        // The bus already names these two; "unknown" is its answer for a code it lacks.
        Code::Coverage => match attitude::coverage_name(v) {
            "unknown" => return None,
            w => w,
        },
        Code::HealthWhy => match integrity::health_why_name(v) {
            "unknown" => return None,
            w => w,
        },
        Code::BahrsHealth => match v {
            attitude::HEALTH_UNAVAILABLE => "unavailable",
            attitude::HEALTH_SAFE => "safe",
            attitude::HEALTH_INTEGRITY_RISK => "integrity_risk",
            attitude::HEALTH_UNDEFINED => "undefined",
            attitude::HEALTH_NONE => "none",
            _ => return None,
        },
        Code::HealthState => match v {
            integrity::HEALTH_AGREE => "agree",
            integrity::HEALTH_DISAGREE => "disagree",
            integrity::HEALTH_NOT_COMPARED => "not_compared",
            _ => return None,
        },
    };
    Some(w)
}

/// The keys of an object that tell what its shared names mean.
#[derive(Debug, Clone, Copy)]
struct Siblings {
    severity: bool,
    disagree_s: bool,
}

/// The concept of the integer code under `key` in an object with the keys `obj`, if any.
/// `state` and `reason` are shared names: an alert's `state` sits beside its `severity`, a
/// health comparison's `state` and `reason` beside `disagree_s`; elsewhere they are left alone.
fn code_of(key: &str, obj: Siblings) -> Option<Code> {
    Some(match key {
        "alert_level" | "raw_alert_level" => Code::AlertLevel,
        "severity" => Code::Severity,
        "state" if obj.severity => Code::AlertState,
        "state" if obj.disagree_s => Code::HealthState,
        "reason" if obj.disagree_s => Code::HealthWhy,
        "address_type" => Code::AddressType,
        "altitude_kind" => Code::AltitudeKind,
        "source" => Code::OwnshipSource,
        "device" => Code::Device,
        "link_state" => Code::LinkState,
        "clock_status" => Code::ClockStatus,
        "isolated_unit" | "vertical_isolated_unit" => Code::Unit,
        "verdict" | "pair_verdicts" => Code::Verdict,
        "isolation" => Code::Isolation,
        "coverage" | "unit_coverage" | "check_coverage" | "vertical_tt_coverage" => Code::Coverage,
        "bahrs_vertical_health" | "bahrs_inertial_health" | "bahrs_navigation_health" => {
            Code::BahrsHealth
        }
        _ => return None,
    })
}

/// Rewrites the integers of `v` (and of its arrays, at any depth) as words of `code`; an
/// integer without a word stays as it is.
fn words(v: &mut Value, code: Code) {
    match v {
        Value::Number(n) => {
            if let Some(w) = n.as_u64().and_then(|x| code_word(code, x)) {
                *v = Value::String(w.to_string());
            }
        }
        Value::Array(items) => items.iter_mut().for_each(|x| words(x, code)),
        _ => {}
    }
}

/// The 24-bit address as six upper-case hex digits.
pub fn hex_address(a: u64) -> String {
    format!("{:06X}", a & 0xFF_FFFF)
}

/// The `_utc` key of a GPS-time key (`t_gps_ns` -> `t_utc`, `gps_time_ns` -> `time_utc`), or
/// `None` when `key` is not a GPS time in ns.
pub fn utc_key(key: &str) -> Option<String> {
    if key == "gps_time_ns" {
        return Some("time_utc".into());
    }
    let stem = key.strip_suffix("_gps_ns")?;
    (!stem.is_empty()).then(|| format!("{stem}_utc"))
}

/// `value` as a JSON value with the names of this module. Serialised to text and parsed back
/// (rather than `serde_json::to_value`) so that f32 fields keep their short f32 text (`0.1`, not
/// `0.10000000149011612`): the decimal an f32 prints as reads back as the f64 that prints the same.
pub fn named_value<T: serde::Serialize + ?Sized>(value: &T) -> serde_json::Result<Value> {
    let mut v: Value = serde_json::from_str(&serde_json::to_string(value)?)?;
    normalise(&mut v);
    Ok(v)
}

/// Applies the names of this module to `v` (see the module documentation), with the usual
/// address keys.
pub fn normalise(v: &mut Value) {
    normalise_with(v, &ADDRESS_KEYS);
}

/// [`normalise`] with its own address keys (`vigil decode` adds MAVLink COLLISION's `id`).
pub fn normalise_with(v: &mut Value, address_keys: &[&str]) {
    match v {
        Value::Object(map) => {
            let siblings = Siblings {
                severity: map.contains_key("severity"),
                disagree_s: map.contains_key("disagree_s"),
            };
            let old = std::mem::take(map);
            let mut out = Map::with_capacity(old.len() + 1);
            for (k, mut val) in old {
                let k = RENAMES
                    .iter()
                    .find(|(from, _)| *from == k)
                    .map_or(k, |(_, to)| (*to).to_string());
                if address_keys.contains(&k.as_str())
                    && let Some(a) = val.as_u64()
                {
                    out.insert(k, Value::String(hex_address(a)));
                    continue;
                }
                if let Some(code) = code_of(&k, siblings) {
                    words(&mut val, code);
                }
                normalise_with(&mut val, address_keys);
                let utc = utc_key(&k).map(|u| (u, utc_value(&val)));
                out.insert(k, val);
                if let Some((u, t)) = utc {
                    out.insert(u, t);
                }
            }
            *map = out;
        }
        Value::Array(items) => items
            .iter_mut()
            .for_each(|x| normalise_with(x, address_keys)),
        _ => {}
    }
}

/// The `_utc` value of a GPS time value: the ISO 8601 string, or null for 0, null or a value
/// that is not an integer.
fn utc_value(v: &Value) -> Value {
    match v.as_i64() {
        Some(t) if t != 0 => Value::String(utc_iso8601(t)),
        _ => Value::Null,
    }
}

/// ISO 8601 UTC (`YYYY-MM-DDTHH:MM:SS.mmmZ`, milliseconds truncated) of a GPS time in ns since
/// the GPS epoch, with the leap seconds of `vigil_fusion::time::gps`'s table. A GPS time inside
/// an inserted leap second is written as second 60 (`2016-12-31T23:59:60.500Z`). Past the table's
/// validity the last known offset is used (a leap second announced since would be missed).
pub fn utc_iso8601(t_gps_ns: i64) -> String {
    // GPS time read as if it were Unix time: at or after the true Unix time, by GPS - UTC.
    let as_unix_ns = t_gps_ns + GPS_EPOCH_UNIX_S * NS_PER_S;
    let offset_at =
        |unix_ns: i64| i64::from(gps_minus_utc_s(unix_ns.div_euclid(NS_PER_S)).gps_minus_utc_s);
    // The offset is non-decreasing and changes at most once within 18 s (leap seconds are
    // months apart): the true offset is the upper bound's or one less. The candidate whose UTC
    // instant the table gives the same offset is it; when neither is, the instant is inside the
    // inserted second (GPS counts it, Unix time does not).
    let hi = offset_at(as_unix_ns);
    let (unix_ns, leap) = [hi, hi - 1]
        .iter()
        .map(|l| as_unix_ns - l * NS_PER_S)
        .zip([hi, hi - 1])
        .find(|(u, l)| offset_at(*u) == *l)
        .map_or((as_unix_ns - hi * NS_PER_S, true), |(u, _)| (u, false));
    let secs = unix_ns.div_euclid(NS_PER_S);
    let ms = unix_ns.rem_euclid(NS_PER_S) / 1_000_000;
    let (y, mo, d) = civil_from_days(secs.div_euclid(S_PER_DAY));
    let sod = secs.rem_euclid(S_PER_DAY);
    let (h, mi, s) = (sod / 3600, sod % 3600 / 60, sod % 60 + i64::from(leap));
    format!("{y:04}-{mo:02}-{d:02}T{h:02}:{mi:02}:{s:02}.{ms:03}Z")
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    const S: i64 = NS_PER_S;

    #[test]
    fn addresses_become_six_hex_digits_at_any_depth() {
        let mut v = json!({
            "address": 11_224_393, // 0xAB4549: 10*16^5+11*16^4+4*16^3+5*16^2+4*16+9
            "traffic": { "address": 1, "alt_pressure_m": 1524.0 },
            "target": { "icao_address": 0xDD1234, "icao": "ABC123" },
            "list": [{ "target_address": 2 }],
            "id": 7,
        });
        normalise(&mut v);
        assert_eq!(v["address"], "AB4549");
        assert_eq!(v["traffic"]["address"], "000001");
        assert_eq!(v["traffic"]["alt_pressure_m"], 1524.0);
        assert_eq!(v["target"]["icao_address"], "DD1234");
        assert_eq!(v["target"]["icao"], "ABC123", "a string stays as it is");
        assert_eq!(v["list"][0]["target_address"], "000002");
        assert_eq!(
            v["id"], 7,
            "`id` is an address only where the caller says so"
        );
        let mut v = json!({ "id": 255 });
        normalise_with(&mut v, &["id"]);
        assert_eq!(v["id"], "0000FF");
    }

    #[test]
    fn codes_become_words_and_unknown_codes_stay_numbers() {
        // Words from the constants' documentation in vigil_bus::payload (DO-365 alert levels
        // 0-3, severities 0-2, states 0-2).
        let mut v = json!({
            "targets": [
                { "alert_level": 3, "raw_alert_level": 1, "address_type": 3, "altitude_kind": 0 },
                { "alert_level": 9, "raw_alert_level": 0, "address_type": 255, "altitude_kind": 7 },
            ],
            "active": [{ "severity": 2, "state": 2 }, { "severity": 7, "state": 1 }],
            "health": [{ "state": 1, "reason": 4, "disagree_s": 0.5 }],
            "state": 1,
            "pair_verdicts": [[0, 1, 2], [2, 2, 9]],
            "source": 1,
            "link_state": 3,
        });
        normalise(&mut v);
        let t = &v["targets"];
        assert_eq!(t[0]["alert_level"], "warning");
        assert_eq!(t[0]["raw_alert_level"], "preventive");
        assert_eq!(t[0]["address_type"], "flarm_random");
        assert_eq!(t[0]["altitude_kind"], "pressure");
        assert_eq!(t[1]["alert_level"], 9);
        assert_eq!(t[1]["raw_alert_level"], "none");
        assert_eq!(t[1]["address_type"], "unknown");
        assert_eq!(t[1]["altitude_kind"], 7);
        assert_eq!(v["active"][0]["severity"], "warning");
        assert_eq!(v["active"][0]["state"], "latched");
        assert_eq!(v["active"][1]["severity"], 7);
        assert_eq!(v["active"][1]["state"], "cleared");
        assert_eq!(v["health"][0]["state"], "disagree");
        assert_eq!(v["health"][0]["reason"], "never_pulsed");
        assert_eq!(v["state"], 1, "a `state` of no known kind stays a number");
        assert_eq!(
            v["pair_verdicts"],
            json!([
                ["pass", "fail", "not_compared"],
                ["not_compared", "not_compared", 9]
            ])
        );
        assert_eq!(v["source"], "vn200_ins");
        assert_eq!(v["link_state"], "disconnected");
    }

    #[test]
    fn loss_of_well_clear_has_one_name() {
        let mut v = json!({
            "time_to_loss_of_well_clear_s": 4.0,
            "geometry": { "loss_of_well_clear_interval_s": [4.0, 9.0] },
        });
        normalise(&mut v);
        assert_eq!(
            v,
            json!({ "time_to_lowc_s": 4.0, "geometry": { "lowc_interval_s": [4.0, 9.0] } })
        );
    }

    #[test]
    fn utc_keys_follow_the_stem() {
        assert_eq!(utc_key("t_gps_ns").as_deref(), Some("t_utc"));
        assert_eq!(utc_key("raised_gps_ns").as_deref(), Some("raised_utc"));
        assert_eq!(utc_key("as_of_gps_ns").as_deref(), Some("as_of_utc"));
        assert_eq!(utc_key("gps_time_ns").as_deref(), Some("time_utc"));
        assert_eq!(utc_key("time_gps_ns").as_deref(), Some("time_utc"));
        assert_eq!(utc_key("t_host_ns"), None);
        assert_eq!(utc_key("_gps_ns"), None);
    }

    #[test]
    fn gps_times_get_a_utc_sibling_and_zero_is_null() {
        // GPS week 1899 began Sunday 2016-05-29 00:00:00 GPS; GPS - UTC was 17 s (leap second of
        // 2015-07-01). UTC 2016-05-31 10:00:01.250 is Tuesday, so GPS time of week
        // 2 d + 10 h + 1.25 s + 17 s = 172 800 + 36 018.25 s.
        let t = 1899 * 604_800 * S + 172_800 * S + 36_018_250_000_000;
        let mut v = json!({
            "header": { "gps_time_ns": t },
            "t_gps_ns": t,
            "raised_gps_ns": 0,
            "cleared_gps_ns": null,
            "t_host_ns": 5,
        });
        normalise(&mut v);
        assert_eq!(v["header"]["time_utc"], "2016-05-31T10:00:01.250Z");
        assert_eq!(v["t_utc"], "2016-05-31T10:00:01.250Z");
        assert_eq!(v["t_gps_ns"], t, "the GPS time stays");
        assert!(v["raised_utc"].is_null());
        assert!(v["cleared_utc"].is_null());
        assert!(v.get("t_host_utc").is_none());
        // Keys keep their order: the UTC sibling right after its GPS time.
        let keys: Vec<&String> = v.as_object().unwrap().keys().collect();
        assert_eq!(keys[1..3], ["t_gps_ns", "t_utc"]);
    }

    #[test]
    fn utc_across_the_leap_second_of_2016_12_31() {
        // Unix 1 483 228 800 s = 2017-01-01 00:00:00 UTC (17 167 days x 86 400 s since 1970);
        // GPS - UTC became 18 s there. GPS seconds = Unix - 315 964 800 (GPS epoch) + offset:
        // 2017-01-01 00:00:00 UTC = 1 167 264 000 + 18 = 1 167 264 018 GPS;
        // 2016-12-31 23:59:59 UTC = 1 167 263 999 + 17 = 1 167 264 016 GPS;
        // the GPS second between them, 1 167 264 017, is the inserted 23:59:60.
        assert_eq!(
            utc_iso8601(1_167_264_016 * S + 999_000_000),
            "2016-12-31T23:59:59.999Z"
        );
        assert_eq!(
            utc_iso8601(1_167_264_017 * S + 500_000_000),
            "2016-12-31T23:59:60.500Z"
        );
        assert_eq!(utc_iso8601(1_167_264_018 * S), "2017-01-01T00:00:00.000Z");
        // Before the first leap second (1981-07-01) GPS and UTC coincide: one day after the
        // epoch is 1980-01-07.
        assert_eq!(
            utc_iso8601(86_400 * S + 1_000_000),
            "1980-01-07T00:00:00.001Z"
        );
        // 2024-02-29 (a leap day): Unix 1 709 164 800 (19 782 days), GPS - UTC 18 s.
        assert_eq!(
            utc_iso8601((1_709_164_800 - 315_964_800 + 18) * S + 12 * 3600 * S),
            "2024-02-29T12:00:00.000Z"
        );
    }
}
