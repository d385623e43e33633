//! FLARM aircraft type to emitter category, manual 8.2.1 table 27 ("FLARM Aircraft Type to
//! Emitter Category translation"; table 28 gives the same numbers for ASTERIX).
//!
//! The module applies this table itself before sending a FLARM target as ADSB_VEHICLE; vigil uses
//! it wherever a FLARM aircraft type arrives raw (CSV `#ALRM`, JSON `flarm.type`) and in the
//! encoders of the simulated module. The categories are the DO-260B / GDL90 / MAVLink
//! `ADSB_EMITTER_TYPE` numbers that [`crate::traffic::TrafficReport::emitter_category`] uses.

/// Emitter category of a FLARM aircraft type (table 27); `None` for a type outside 0..=15.
pub fn flarm_aircraft_type_to_emitter(aircraft_type: u8) -> Option<u8> {
    Some(match aircraft_type {
        0 => 0,      // reserved -> no information
        1 => 9,      // glider, motor glider -> glider
        2 => 1,      // tow plane, tug plane -> light
        3 => 7,      // helicopter, gyrocopter, rotorcraft -> rotorcraft
        4 => 11,     // skydiver, parachute -> parachute
        5 => 1,      // drop plane for skydivers -> light
        6 | 7 => 12, // hang glider (hard / soft) -> ultra light
        8 => 1,      // aircraft with reciprocating engine -> light
        9 => 3,      // aircraft with jet / turboprop engine -> large
        10 => 0,     // reserved -> no information
        11 => 10,    // balloon -> lighter than air
        12 => 10,    // airship, blimp, zeppelin -> lighter than air
        13 => 14,    // unmanned aerial vehicle -> UAV
        14 => 0,     // reserved -> no information
        15 => 0,     // static obstacle -> no information
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_27() {
        // Table 27, row by row (aircraft type -> emitter category index).
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
        for (t, e) in table {
            assert_eq!(flarm_aircraft_type_to_emitter(t), Some(e), "type {t}");
        }
        assert_eq!(flarm_aircraft_type_to_emitter(16), None);
        assert_eq!(flarm_aircraft_type_to_emitter(255), None);
    }
}
