//! The C contract of the bus (issue 26): the committed C header is what cbindgen generates from
//! this crate now, and a C program whose sizes and offsets come from the Rust layout
//! (`offset_of!`, `size_of`) compiles against it, with `_Static_assert`s, in C and in C++.
//!
//! Generated and committed (regenerate with `VIGIL_BLESS=1 cargo test -p vigil-bus --test
//! c_layout`, then review the diff):
//! - `bus/include/vigil_bus.h`: the header (cbindgen, `bus/cbindgen.toml`);
//! - `bus/c/layout_check.c`: the static assertions (from the Rust layout);
//! - `bus/include/vigil_bus_layout.json`: the same sizes and offsets, for the Python package's
//!   test (`bus/python/tests`).

use std::mem::{align_of, offset_of, size_of};
use std::path::{Path, PathBuf};
use std::process::Command;

use vigil_bus::payload::traffic::TrafficHeader;
use vigil_bus::{
    AlertPayload, AttitudePayload, DeviceIntegrity, Header, IntegrityPayload, OwnshipPayload,
    Target, UnitAttitude,
};

/// One struct's layout as Rust lays it out.
struct Layout {
    /// C name (cbindgen's export prefix + the Rust name).
    c_name: String,
    size: usize,
    align: usize,
    /// (field, offset, size) in declaration order.
    fields: Vec<(&'static str, usize, usize)>,
}

/// Size of a field, from a typed null-free projection (no value of the struct is needed).
fn field_size<S, F>(_: fn(&S) -> &F) -> usize {
    size_of::<F>()
}

macro_rules! layout {
    ($ty:ty { $($field:ident),* $(,)? }) => {
        Layout {
            c_name: format!("vigil_{}", stringify!($ty)),
            size: size_of::<$ty>(),
            align: align_of::<$ty>(),
            fields: vec![$((
                stringify!($field),
                offset_of!($ty, $field),
                field_size(|s: &$ty| &s.$field),
            )),*],
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
            reserved
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
            reserved
        }),
        layout!(Target {
            address,
            address_type,
            alert_level,
            altitude_kind,
            plausibility_flags,
            callsign,
            emitter_category,
            sources,
            nic,
            nac_p,
            nac_v,
            sil,
            reserved,
            flags,
            reserved2,
            lat_deg,
            lon_deg,
            alt_pressure_m,
            alt_geometric_m,
            track_deg,
            ground_speed_mps,
            vertical_rate_mps,
            position_sigma_m,
            age_s,
            rel_north_m,
            rel_east_m,
            rel_down_m,
            rel_vel_north_mps,
            rel_vel_east_mps,
            rel_vel_down_mps,
            horizontal_distance_m,
            vertical_separation_m,
            bearing_deg,
            range_rate_mps,
            tcpa_s,
            hmd_m,
            tau_mod_s,
            time_to_lowc_s
        }),
        layout!(TrafficHeader {
            header,
            count,
            dropped
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
            reconnects
        }),
        layout!(IntegrityPayload {
            header,
            device_count,
            clock_status,
            leap_seconds_known,
            reserved,
            clock_offset_s,
            clock_sigma_s,
            devices
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

/// Compares `text` with the committed file `rel` (or writes it with `VIGIL_BLESS=1`).
fn check_committed(rel: &str, text: &str) {
    let path = bus_dir().join(rel);
    if std::env::var_os("VIGIL_BLESS").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, text).unwrap();
        return;
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == text,
        "{rel} is not current: regenerate it with \
         `VIGIL_BLESS=1 cargo test -p vigil-bus --test c_layout` and review the diff"
    );
}

fn generate_header() -> String {
    let config = cbindgen::Config::from_file(bus_dir().join("cbindgen.toml")).unwrap();
    let bindings = cbindgen::Builder::new()
        .with_crate(bus_dir())
        .with_config(config)
        .generate()
        .expect("cbindgen generates the header");
    let mut out = Vec::new();
    bindings.write(&mut out);
    String::from_utf8(out).unwrap()
}

/// The C program: one `_Static_assert` per size, alignment and field offset.
fn layout_check_c(layouts: &[Layout]) -> String {
    let mut c = String::from(
        "/* Generated by bus/tests/c_layout.rs from the Rust layout of vigil-bus (offset_of!,\n \
         * size_of); do not edit. Compiled and run by that test, in C11 and C++17: a consumer may\n \
         * compile it in its own build to check its copy of vigil_bus.h. */\n\
         #include <stdalign.h>\n#include <stddef.h>\n#include <stdio.h>\n\n#include \"vigil_bus.h\"\n\n\
         #ifdef __cplusplus\n#define VIGIL_STATIC_ASSERT static_assert\n#else\n\
         #define VIGIL_STATIC_ASSERT _Static_assert\n#endif\n\n",
    );
    for l in layouts {
        let n = &l.c_name;
        c += &format!(
            "VIGIL_STATIC_ASSERT(sizeof({n}) == {}, \"size of {n}\");\n",
            l.size
        );
        c += &format!(
            "VIGIL_STATIC_ASSERT(alignof({n}) == {}, \"alignment of {n}\");\n",
            l.align
        );
        for (f, off, size) in &l.fields {
            c += &format!(
                "VIGIL_STATIC_ASSERT(offsetof({n}, {f}) == {off}, \"offset of {n}.{f}\");\n"
            );
            c += &format!(
                "VIGIL_STATIC_ASSERT(sizeof((({n} *)0)->{f}) == {size}, \"size of {n}.{f}\");\n"
            );
        }
        c += "\n";
    }
    c += "int main(void) {\n    puts(\"vigil_bus.h layout ok\");\n    return 0;\n}\n";
    c
}

/// The layouts as JSON, for other languages' tests.
fn layout_json(layouts: &[Layout]) -> String {
    let v: serde_json::Map<String, serde_json::Value> = layouts
        .iter()
        .map(|l| {
            let fields: Vec<serde_json::Value> = l
                .fields
                .iter()
                .map(|(f, off, size)| serde_json::json!({"name": f, "offset": off, "size": size}))
                .collect();
            (
                l.c_name.clone(),
                serde_json::json!({"size": l.size, "align": l.align, "fields": fields}),
            )
        })
        .collect();
    let mut s = serde_json::to_string_pretty(&serde_json::json!({
        "schema_version": vigil_bus::SCHEMA_VERSION,
        "max_targets": vigil_bus::MAX_TARGETS,
        "structs": v,
    }))
    .unwrap();
    s.push('\n');
    s
}

/// The field names of `typedef struct NAME { ... } NAME;` in the header, in order.
fn header_fields(header: &str, name: &str) -> Vec<String> {
    let start = header
        .find(&format!("typedef struct {name} {{"))
        .unwrap_or_else(|| panic!("{name} missing from the header"));
    let body = &header[start..];
    let body = &body[body.find('{').unwrap() + 1..body.find('}').unwrap()];
    body.lines()
        .map(str::trim)
        // Declarations only: doc comments (`/**`, ` *`, `*/` lines) may end in ';' too.
        .filter(|l| l.ends_with(';') && !l.starts_with('*') && !l.starts_with('/'))
        .map(|l| {
            let decl = l.trim_end_matches(';');
            let decl = decl.split('[').next().unwrap();
            decl.split_whitespace().last().unwrap().to_string()
        })
        .collect()
}

fn compile_and_run(compiler: &str, std: &str, source: &Path, out: &Path) -> Option<String> {
    let status = Command::new(compiler)
        .args([std, "-Wall", "-Wextra", "-Werror", "-pedantic"])
        .arg("-I")
        .arg(bus_dir().join("include"))
        .arg(source)
        .arg("-o")
        .arg(out)
        .status();
    match status {
        Ok(s) => assert!(s.success(), "{compiler} failed on {}", source.display()),
        // No such compiler on this machine.
        Err(_) => return None,
    }
    let run = Command::new(out).output().unwrap();
    assert!(run.status.success());
    Some(String::from_utf8_lossy(&run.stdout).into_owned())
}

#[test]
fn c_header_is_current_and_matches_the_rust_layout() {
    let header = generate_header();
    check_committed("include/vigil_bus.h", &header);
    let layouts = layouts();
    // Every field of the header's structs is checked (none missing from the lists above), in
    // the same order.
    for l in &layouts {
        let names: Vec<&str> = l.fields.iter().map(|f| f.0).collect();
        assert_eq!(header_fields(&header, &l.c_name), names, "{}", l.c_name);
    }
    let c = layout_check_c(&layouts);
    check_committed("c/layout_check.c", &c);
    check_committed("include/vigil_bus_layout.json", &layout_json(&layouts));

    // CI has a C compiler (the Rust toolchain links with it): C11 is required; C++17 is checked
    // when a C++ compiler is present too.
    let dir = std::env::temp_dir().join(format!("vigil-c-layout-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let src = dir.join("layout_check.c");
    std::fs::write(&src, &c).unwrap();
    let out = compile_and_run("cc", "-std=c11", &src, &dir.join("layout_check"))
        .expect("a C compiler (cc) is required");
    assert_eq!(out.trim(), "vigil_bus.h layout ok");
    let cpp = dir.join("layout_check.cpp");
    std::fs::write(&cpp, &c).unwrap();
    if let Some(out) = compile_and_run("c++", "-std=c++17", &cpp, &dir.join("layout_check_cpp")) {
        assert_eq!(out.trim(), "vigil_bus.h layout ok");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
