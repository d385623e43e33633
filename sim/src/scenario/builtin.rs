//! The built-in named scenarios, kept as TOML files under `sim/scenarios/` (they double as
//! examples of the scenario format).

use super::{Scenario, ScenarioError};

/// Names of the built-in scenarios.
pub const BUILTIN_NAMES: [&str; 13] = [
    "nominal",
    "headon",
    "crossing",
    "busy-airspace",
    "bahrs-attitude-fault",
    "gnss-outage",
    "spoofed-target",
    "link-errors",
    "magnetic-disturbance",
    "vn200-gnss-loss",
    "demo",
    "bahrs-pressure-port",
    "bahrs-gyro-bias",
];

fn text(name: &str) -> Option<&'static str> {
    Some(match name {
        "nominal" => include_str!("../../scenarios/nominal.toml"),
        "headon" => include_str!("../../scenarios/headon.toml"),
        "crossing" => include_str!("../../scenarios/crossing.toml"),
        "busy-airspace" => include_str!("../../scenarios/busy-airspace.toml"),
        "bahrs-attitude-fault" => include_str!("../../scenarios/bahrs-attitude-fault.toml"),
        "gnss-outage" => include_str!("../../scenarios/gnss-outage.toml"),
        "spoofed-target" => include_str!("../../scenarios/spoofed-target.toml"),
        "link-errors" => include_str!("../../scenarios/link-errors.toml"),
        "magnetic-disturbance" => include_str!("../../scenarios/magnetic-disturbance.toml"),
        "vn200-gnss-loss" => include_str!("../../scenarios/vn200-gnss-loss.toml"),
        "demo" => include_str!("../../scenarios/demo.toml"),
        "bahrs-pressure-port" => include_str!("../../scenarios/bahrs-pressure-port.toml"),
        "bahrs-gyro-bias" => include_str!("../../scenarios/bahrs-gyro-bias.toml"),
        _ => return None,
    })
}

/// The built-in scenario `name`.
pub fn builtin(name: &str) -> Result<Scenario, ScenarioError> {
    let t = text(name).ok_or_else(|| ScenarioError::Unknown(name.to_string()))?;
    Scenario::from_toml(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_builtin_loads_and_carries_its_name() {
        for name in BUILTIN_NAMES {
            let s = builtin(name).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(s.name, name);
            // Round trip through TOML gives the same scenario.
            assert_eq!(Scenario::from_toml(&s.to_toml()).unwrap(), s, "{name}");
        }
        assert_eq!(builtin("nominal").unwrap().all_intruders().len(), 5);
        assert_eq!(builtin("busy-airspace").unwrap().all_intruders().len(), 300);
        assert!(matches!(builtin("nope"), Err(ScenarioError::Unknown(_))));
    }

    /// Issue 25: the two BAHRS faults are declared in scenario TOML like the others.
    #[test]
    fn issue_25_bahrs_faults_parse_from_toml() {
        let t = format!(
            "{}\n[[faults]]\nkind = \"pressure_port_blocked\"\nfrom_s = 10.0\nto_s = 25.0\n\n\
             [[faults]]\nkind = \"bahrs_gyro_bias\"\nfrom_s = 5.0\naxis = \"y\"\n\
             rate_dps_per_s = 0.05\n",
            text("nominal").unwrap()
        );
        let s = Scenario::from_toml(&t).unwrap();
        assert_eq!(
            s.faults,
            [
                super::super::Fault::PressurePortBlocked {
                    from_s: 10.0,
                    to_s: Some(25.0)
                },
                super::super::Fault::BahrsGyroBias {
                    from_s: 5.0,
                    to_s: None,
                    axis: super::super::BodyAxis::Y,
                    bias_dps: 0.0,
                    rate_dps_per_s: 0.05
                }
            ]
        );
        let bad = t.replace("to_s = 25.0", "to_s = 5.0");
        let e = Scenario::from_toml(&bad).unwrap_err().to_string();
        assert!(e.contains("to_s"), "{e}");
    }

    /// Issue 25 point 6: the VN-200 vertical drift is declared in scenario TOML too.
    #[test]
    fn issue_25_vn200_vertical_drift_parses_from_toml() {
        let t = format!(
            "{}\n[[faults]]\nkind = \"vn200_vertical_drift\"\nfrom_s = 10.0\nto_s = 45.0\n\
             rate_mps = 3.0\n",
            text("nominal").unwrap()
        );
        let s = Scenario::from_toml(&t).unwrap();
        assert_eq!(
            s.faults,
            [super::super::Fault::Vn200VerticalDrift {
                from_s: 10.0,
                to_s: Some(45.0),
                rate_mps: 3.0
            }]
        );
    }

    #[test]
    fn bad_key_is_named() {
        let t = text("headon")
            .unwrap()
            .replace("speed_mps = 40.0", "speed_mps = 4000.0");
        let e = Scenario::from_toml(&t).unwrap_err().to_string();
        assert!(e.contains("ownship.speed_mps"), "{e}");
        let t = text("headon")
            .unwrap()
            .replace("track_deg = 0.0", "trak_deg = 0.0");
        let e = Scenario::from_toml(&t).unwrap_err().to_string();
        assert!(e.contains("trak_deg"), "{e}");
    }

    #[test]
    fn bad_faults_are_named() {
        let base = text("link-errors").unwrap();
        for (from, to, key) in [
            (
                "device = \"watson\"\nfrom_s = 25.0",
                "device = \"gps\"\nfrom_s = 25.0",
                "faults[4].device",
            ),
            ("rate = 1.0e-4", "rate = 0.9", "faults[2].rate"),
            (
                "from_s = 20.0\nto_s = 22.0",
                "from_s = 20.0\nto_s = 19.0",
                "faults[3].to_s",
            ),
            ("at_s = 40.0", "at_s = -1.0", "faults[5].from_s"),
        ] {
            assert!(base.contains(from), "{from}");
            let e = Scenario::from_toml(&base.replacen(from, to, 1))
                .unwrap_err()
                .to_string();
            assert!(e.contains(key), "{key}: {e}");
        }
    }
}
