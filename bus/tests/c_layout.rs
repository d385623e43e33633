//! The C contract of the bus (issue 26): the committed C header is what cbindgen generates from
//! this crate now, and a C program whose sizes and offsets come from the Rust layout
//! (`offset_of!`, `size_of`, `align_of`) compiles against it with static assertions, as C11 and
//! as C++17. The field lists below are checked against the payload sources, so a field added to
//! a payload without its check fails here.
//!
//! Generated and committed (regenerate with `VIGIL_BLESS=1 cargo test -p vigil-bus --test
//! c_layout`, then review the diff): `bus/include/vigil_bus.h` (cbindgen, `bus/cbindgen.toml`)
//! and `bus/c/layout_check.c` (from the Rust layout).

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::mem::{align_of, offset_of, size_of};
use std::path::{Path, PathBuf};
use std::process::Command;

use iceoryx2::prelude::ZeroCopySend;

use vigil_bus::payload::attitude::ChannelComparison;
use vigil_bus::payload::integrity::{ActiveAlert, HealthComparison};
use vigil_bus::{
    AlertPayload, AttitudePayload, DeviceIntegrity, Header, IntegrityPayload, OwnshipPayload,
    Target, TrafficHeader, UnitAttitude,
};

/// One struct's layout as Rust lays it out.
struct Layout {
    name: &'static str,
    /// The iceoryx2 type name (`#[type_name(...)]`), which a subscriber must give too.
    type_name: &'static str,
    size: usize,
    align: usize,
    /// (field, offset, size, Rust type) in declaration order.
    fields: Vec<(&'static str, usize, usize, &'static str)>,
}

/// Size and Rust type name of a field, from a typed projection (no value is needed).
fn field_type<S, F>(_: fn(&S) -> &F) -> (usize, &'static str) {
    (size_of::<F>(), std::any::type_name::<F>())
}

fn iox_type_name<T: ZeroCopySend>() -> &'static str {
    // SAFETY: `type_name` only returns the string the derive stored; it has no precondition
    // beyond being called on a ZeroCopySend type (it is unsafe because implementers may pick any
    // name, which is what this test records).
    unsafe { <T as ZeroCopySend>::type_name() }
}

macro_rules! layout {
    ($ty:ident { $($field:ident),* $(,)? }) => {
        Layout {
            name: stringify!($ty),
            type_name: iox_type_name::<$ty>(),
            size: size_of::<$ty>(),
            align: align_of::<$ty>(),
            fields: vec![$({
                let (size, ty) = field_type(|s: &$ty| &s.$field);
                (stringify!($field), offset_of!($ty, $field), size, ty)
            }),*],
        }
    };
}

fn layouts() -> Vec<Layout> {
    vec![
        layout!(Header {
            schema_version,
            reserved,
            seq,
            gps_time_ns,
            send_mono_ns
        }),
        layout!(UnitAttitude {
            t_gps_ns,
            roll_rad,
            pitch_rad,
            heading_rad,
            sigma_roll_rad,
            sigma_pitch_rad,
            sigma_heading_rad,
            valid,
            fault_flags,
            reserved
        }),
        layout!(ChannelComparison {
            bahrs,
            vn200,
            diff,
            sigma,
            stat_ratio,
            verdict,
            coverage,
            reserved
        }),
        layout!(AttitudePayload {
            header,
            roll_rad,
            pitch_rad,
            heading_rad,
            sigma_roll_rad,
            sigma_pitch_rad,
            sigma_heading_rad,
            units,
            pair_verdicts,
            isolation,
            isolated_unit,
            valid,
            reserved,
            unit_coverage,
            check_coverage,
            reserved_coverage,
            unit_compared_age_s,
            check_compared_age_s,
            vertical,
            inertial,
            bahrs_vertical_health,
            bahrs_inertial_health,
            vertical_tt_rate_mps,
            vertical_tt,
            vertical_tt_coverage,
            vertical_isolated_unit,
            reserved_vertical_tt
        }),
        layout!(OwnshipPayload {
            header,
            lat_deg,
            lon_deg,
            alt_pressure_m,
            alt_geometric_m,
            vel_north_mps,
            vel_east_mps,
            vel_up_mps,
            ground_speed_mps,
            track_deg,
            sigma_horizontal_m,
            sigma_vertical_m,
            sigma_velocity_mps,
            source,
            valid,
            flags,
            reserved
        }),
        layout!(Target {
            address,
            address_type,
            alert_level,
            altitude_kind,
            plausibility_flags,
            callsign,
            lat_deg,
            lon_deg,
            alt_pressure_m,
            alt_geometric_m,
            track_deg,
            ground_speed_mps,
            vertical_rate_mps,
            position_sigma_m,
            nic,
            nac_p,
            nac_v,
            emitter_category,
            sources,
            reserved,
            rel_north_m,
            rel_east_m,
            rel_down_m,
            rel_vel_north_mps,
            rel_vel_east_mps,
            rel_vel_down_mps,
            horizontal_distance_m,
            bearing_deg,
            range_rate_mps,
            tcpa_s,
            hmd_m,
            tau_mod_s,
            time_to_lowc_s,
            age_s,
            flags
        }),
        layout!(TrafficHeader {
            header,
            count,
            dropped
        }),
        layout!(ActiveAlert {
            alert_id,
            severity,
            state,
            reserved,
            raised_gps_ns,
            reason
        }),
        layout!(HealthComparison {
            state,
            reason,
            reserved,
            disagree_s
        }),
        layout!(DeviceIntegrity {
            name,
            device,
            link_state,
            reserved,
            last_message_age_s,
            bytes_received,
            bytes_consumed,
            bytes_skipped,
            messages,
            checksum_failures,
            unknown_types,
            malformed,
            reconnects,
            invalid_values
        }),
        layout!(IntegrityPayload {
            header,
            device_count,
            clock_status,
            leap_seconds_known,
            reserved,
            clock_offset_s,
            clock_sigma_s,
            devices,
            clock_disagreement,
            line_full,
            reserved_clock,
            active_alert_count,
            active_alert_total,
            active_alerts,
            bahrs_navigation_health,
            bahrs_inertial_health,
            vn200_ins_mode,
            vn200_gnss_fix,
            reserved_health,
            vn200_ins_status,
            vn200_status_age_s,
            bahrs_pulse_age_s,
            health_checks
        }),
        layout!(AlertPayload {
            header,
            alert_id,
            severity,
            state,
            reserved,
            raised_gps_ns,
            reason
        }),
    ]
}

fn bus_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `pub struct NAME { pub field: ... }` field names of every `#[repr(C)]` struct of the payload
/// source files (the wire types; `TrafficPayload`, the picture owned in a process, is not one).
fn source_fields() -> BTreeMap<String, Vec<String>> {
    let mut out = BTreeMap::new();
    let dir = bus_dir().join("src/payload");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        let mut current: Option<(String, Vec<String>)> = None;
        let mut repr_c = false;
        for line in text.lines() {
            if line == "#[repr(C)]" {
                repr_c = true;
            } else if let Some(rest) = line.strip_prefix("pub struct ") {
                if let Some(name) = rest.strip_suffix(" {")
                    && std::mem::take(&mut repr_c)
                {
                    current = Some((name.to_string(), Vec::new()));
                }
            } else if line == "}" {
                if let Some((name, fields)) = current.take() {
                    out.insert(name, fields);
                }
            } else if let Some((_, fields)) = &mut current
                && let Some(rest) = line.trim_start().strip_prefix("pub ")
                && let Some((field, _)) = rest.split_once(':')
            {
                fields.push(field.to_string());
            }
        }
    }
    out
}

#[test]
fn every_payload_field_is_checked() {
    let src = source_fields();
    let checked: BTreeMap<String, Vec<String>> = layouts()
        .iter()
        .map(|l| {
            (
                l.name.to_string(),
                l.fields.iter().map(|f| f.0.to_string()).collect(),
            )
        })
        .collect();
    assert_eq!(checked, src, "update the layout! lists in this test");
}

/// The header cbindgen generates from the crate now.
fn generate_header() -> String {
    let config = cbindgen::Config::from_file(bus_dir().join("cbindgen.toml")).unwrap();
    let bindings = cbindgen::Builder::new()
        .with_crate(bus_dir())
        .with_config(config)
        .generate()
        .expect("cbindgen");
    let mut out = Vec::new();
    bindings.write(&mut out);
    String::from_utf8(out).unwrap()
}

/// The C source of the static assertions.
fn layout_check_c() -> String {
    let mut s = String::from(
        "/* Generated by bus/tests/c_layout.rs from the Rust layout of vigil-bus (offset_of!,\n \
         * size_of, align_of); do not edit. Compiled by that test as C11 and C++17; a consumer may\n \
         * compile it in its own build to check its copy of vigil_bus.h. */\n\
         #include <stddef.h>\n\n#include \"vigil_bus.h\"\n\n\
         #ifdef __cplusplus\n#define VIGIL_ASSERT static_assert\n#define VIGIL_ALIGNOF alignof\n\
         #else\n#define VIGIL_ASSERT _Static_assert\n#define VIGIL_ALIGNOF _Alignof\n#endif\n",
    );
    for l in layouts() {
        let c = format!("vigil_{}", l.name);
        let _ = writeln!(s);
        let _ = writeln!(
            s,
            "VIGIL_ASSERT(sizeof({c}) == {}, \"size of {c}\");",
            l.size
        );
        let _ = writeln!(
            s,
            "VIGIL_ASSERT(VIGIL_ALIGNOF({c}) == {}, \"alignment of {c}\");",
            l.align
        );
        for (f, off, size, _) in &l.fields {
            let _ = writeln!(
                s,
                "VIGIL_ASSERT(offsetof({c}, {f}) == {off}, \"offset of {c}.{f}\");"
            );
            let _ = writeln!(
                s,
                "VIGIL_ASSERT(sizeof((({c} *)0)->{f}) == {size}, \"size of {c}.{f}\");"
            );
        }
    }
    s.push_str("\nint main(void) { return 0; }\n");
    s
}

/// The ctypes type of a Rust field type (`f64`, `[u8; 16]`, `[path::UnitAttitude; 3]`, ...).
fn ctype(rust: &str) -> String {
    if let Some(inner) = rust.strip_prefix('[').and_then(|r| r.strip_suffix(']')) {
        let (elem, n) = inner.rsplit_once("; ").expect("an array type");
        return format!("({}) * {n}", ctype(elem));
    }
    match rust {
        "u8" => "ctypes.c_uint8",
        "u16" => "ctypes.c_uint16",
        "u32" => "ctypes.c_uint32",
        "u64" => "ctypes.c_uint64",
        "i8" => "ctypes.c_int8",
        "i16" => "ctypes.c_int16",
        "i32" => "ctypes.c_int32",
        "i64" => "ctypes.c_int64",
        "f32" => "ctypes.c_float",
        "f64" => "ctypes.c_double",
        "bool" => "ctypes.c_bool",
        path => return path.rsplit("::").next().unwrap().to_string(),
    }
    .to_string()
}

/// The Python module of the payloads: ctypes structures generated from the same layout, each
/// with the iceoryx2 type name, and their sizes and offsets for its own test to check.
fn payloads_py() -> String {
    let mut s = String::from(
        "\"\"\"vigil's bus payloads as ctypes structures, for the iceoryx2 Python package.\n\n\
         Generated by bus/tests/c_layout.rs from the Rust layout of vigil-bus; do not edit.\n\
         Regenerate: VIGIL_BLESS=1 cargo test -p vigil-bus --test c_layout\n\"\"\"\n\n\
         import ctypes\n\n",
    );
    let mut sizes = String::from(
        "# (size, alignment, {field: (offset, size)}) per structure, from Rust.\nLAYOUT = {\n",
    );
    for l in layouts() {
        let _ = writeln!(s, "\nclass {}(ctypes.Structure):", l.name);
        let _ = writeln!(s, "    \"\"\"iceoryx2 type name `{}`.\"\"\"\n", l.type_name);
        let _ = writeln!(s, "    _fields_ = [");
        for (f, _, _, ty) in &l.fields {
            let _ = writeln!(s, "        (\"{f}\", {}),", ctype(ty));
        }
        let _ = writeln!(s, "    ]\n");
        let _ = writeln!(s, "    @staticmethod\n    def type_name() -> str:");
        let _ = writeln!(s, "        return \"{}\"\n", l.type_name);
        let fields: Vec<String> = l
            .fields
            .iter()
            .map(|(f, off, size, _)| format!("\"{f}\": ({off}, {size})"))
            .collect();
        let _ = writeln!(
            sizes,
            "    \"{}\": ({}, {}, {{{}}}),",
            l.name,
            l.size,
            l.align,
            fields.join(", ")
        );
    }
    sizes.push_str("}\n");
    s.push('\n');
    s.push_str(&sizes);
    s
}

/// Compares `text` with the committed file, or writes it with `VIGIL_BLESS=1`.
fn check_committed(path: &Path, text: &str) {
    if std::env::var_os("VIGIL_BLESS").is_some() {
        std::fs::write(path, text).unwrap();
        return;
    }
    let committed = std::fs::read_to_string(path).unwrap_or_default();
    assert!(
        committed == text,
        "{} is stale: regenerate with VIGIL_BLESS=1 cargo test -p vigil-bus --test c_layout and \
         review the diff",
        path.display()
    );
}

#[test]
fn the_header_is_current_and_the_layout_check_compiles_as_c_and_cpp() {
    let include = bus_dir().join("include");
    check_committed(&include.join("vigil_bus.h"), &generate_header());
    let check = bus_dir().join("c/layout_check.c");
    check_committed(&check, &layout_check_c());
    check_committed(
        &bus_dir().join("python/vigil_bus/payloads.py"),
        &payloads_py(),
    );
    // Compiled, not only parsed: every static assertion is evaluated. CI has a C and a C++
    // compiler; elsewhere a missing one is said and skipped.
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
    for (compiler, std, lang) in [("cc", "-std=c11", "c"), ("c++", "-std=c++17", "c++")] {
        let run = Command::new(compiler)
            .arg(std)
            .args(["-Wall", "-Werror", "-x", lang])
            .arg("-I")
            .arg(&include)
            .arg(&check)
            .arg("-o")
            .arg(out.join(format!("layout_check_{lang}")))
            .output();
        match run {
            Ok(o) => assert!(
                o.status.success(),
                "{compiler} {std}: {}",
                String::from_utf8_lossy(&o.stderr)
            ),
            Err(e) if std::env::var_os("CI").is_none() => {
                eprintln!("skipped: {compiler} not available ({e})");
            }
            Err(e) => panic!("{compiler}: {e} (CI must compile the layout check)"),
        }
    }
}
