//! Issue 25: "README: the integrity section's table of rules is complete and matches the code".
//! Every rule of [`Rule::ALL`] has exactly one row in the README's alert table, with its code,
//! default severity, raise delay and clear hysteresis as the code has them.

use vigil_bus::payload::alerts::{SEVERITY_ADVISORY, SEVERITY_CAUTION, SEVERITY_WARNING};
use vigil_monitor::{Rule, RuleTiming};

const README: &str = include_str!("../../README.md");

fn rows() -> Vec<Vec<String>> {
    README
        .lines()
        // The rule table's rows: the first cell is "`name` (0xCODE...".
        .filter(|l| {
            l.starts_with("| `") && l.split(" | ").next().is_some_and(|c| c.contains("` (0x"))
        })
        .map(|l| {
            l.trim_matches('|')
                .split(" | ")
                .map(|c| c.trim().to_string())
                .collect()
        })
        .collect()
}

#[test]
fn every_rule_has_one_readme_row_matching_the_code() {
    let rows = rows();
    assert_eq!(rows.len(), Rule::ALL.len(), "{rows:#?}");
    for rule in Rule::ALL {
        let head = format!("`{}` (0x{:02X}", rule.name(), rule.code());
        let matching: Vec<_> = rows.iter().filter(|r| r[0].starts_with(&head)).collect();
        assert_eq!(matching.len(), 1, "{head}: {rows:#?}");
        let r = matching[0];
        let t = RuleTiming::default_for(rule);
        let num = |s: &str| s.parse::<f64>().unwrap();
        assert_eq!(num(&r[3]), t.raise_delay_s, "{head}");
        assert_eq!(num(&r[4]), t.clear_hysteresis_s, "{head}");
        // Rules with a severity that depends on the value list several; the highest is the code's.
        let highest = match rule.severity() {
            SEVERITY_ADVISORY => "advisory",
            SEVERITY_CAUTION => "caution",
            SEVERITY_WARNING => "warning",
            s => panic!("severity {s}"),
        };
        assert!(
            r[2].ends_with(highest) || r[2] == "by level",
            "{head}: {} vs {highest}",
            r[2]
        );
    }
}
