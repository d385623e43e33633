//! FLARM aircraft types (manual table 26 / table 30) and their translation to emitter categories
//! (manual table 27 for MAVLink, table 28 for ASTERIX: both tables are identical).
//!
//! The emitter category numbers are those of the CSV `ECAT` field (table 17), which are the
//! DO-260B / GDL90 emitter categories that [`crate::traffic::TrafficReport::emitter_category`]
//! uses. Every protocol that carries FLARM targets (CSV `#ALRM`, JSON `flarm`, MAVLink, ASTERIX)
//! maps through [`emitter_category`], so a FLARM glider is category 9 whatever delivered it.

/// Emitter category for a FLARM aircraft type, manual table 27. Types outside 0..=15 (the field
/// is four bits wide on the FLARM radio) have no information: 0.
pub const fn emitter_category(flarm_aircraft_type: u8) -> u8 {
    match flarm_aircraft_type {
        1 => 9,        // glider, motor glider -> glider
        2 => 1,        // tow plane -> light
        3 => 7,        // helicopter, gyrocopter -> rotorcraft
        4 => 11,       // skydiver, parachute -> parachute
        5 => 1,        // drop plane -> light
        6 | 7 => 12,   // hang glider hard / soft -> ultralight
        8 => 1,        // reciprocating engine -> light
        9 => 3,        // jet / turboprop -> large
        11 | 12 => 10, // balloon, airship -> lighter than air
        13 => 14,      // UAV -> UAV
        // 0, 10, 14 reserved; 15 static obstacle: "No information" in table 27.
        _ => 0,
    }
}

/// Short description of a FLARM aircraft type (manual table 26), for logs and decode output.
pub const fn aircraft_type_name(flarm_aircraft_type: u8) -> &'static str {
    match flarm_aircraft_type {
        1 => "glider",
        2 => "tow_plane",
        3 => "helicopter",
        4 => "parachute",
        5 => "drop_plane",
        6 => "hang_glider_hard",
        7 => "hang_glider_soft",
        8 => "piston_engine",
        9 => "jet_turboprop",
        11 => "balloon",
        12 => "airship",
        13 => "uav",
        15 => "static_obstacle",
        _ => "reserved",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_27_row_by_row() {
        // (aircraft type, emitter category) transcribed from manual table 27.
        let table = [
            (0, 0),
            (1, 9),
            (2, 1),
            (3, 7),
            (4, 11),
            (5, 1),
            (6, 12),
            (7, 12),
            (8, 1),
            (9, 3),
            (10, 0),
            (11, 10),
            (12, 10),
            (13, 14),
            (14, 0),
            (15, 0),
        ];
        for (t, cat) in table {
            assert_eq!(emitter_category(t), cat, "FLARM type {t}");
        }
        assert_eq!(emitter_category(16), 0);
        assert_eq!(emitter_category(255), 0);
        assert_eq!(aircraft_type_name(13), "uav");
        assert_eq!(aircraft_type_name(200), "reserved");
    }
}
