//! A progress bar on stderr for long `vigil sim` / `vigil replay` runs, drawn only when stderr is
//! a terminal (so logs, pipes and tests see nothing of it).
//!
//! Written here rather than with `indicatif` (not in the workspace's package list): one line,
//! redrawn in place with `\r` when its text changes (at most once per permille), cleared at the
//! end. Progress is measured in the run's own time (simulated or recorded seconds), not in wall
//! time, so the bar says how far the data has got.

use std::io::IsTerminal;

/// Width of the bar between the brackets, characters.
const WIDTH: usize = 30;

/// A one-line progress bar over `0 ..= total` units of nanoseconds of run time.
#[derive(Debug)]
pub struct ProgressBar {
    label: &'static str,
    total_ns: u64,
    shown_permille: Option<u64>,
    enabled: bool,
}

impl ProgressBar {
    /// A bar for `total_ns` of run time, shown when stderr is a terminal.
    pub fn stderr(label: &'static str, total_ns: u64) -> Self {
        Self::new(label, total_ns, std::io::stderr().is_terminal())
    }

    /// A bar that draws only when `enabled`.
    pub fn new(label: &'static str, total_ns: u64, enabled: bool) -> Self {
        Self {
            label,
            total_ns: total_ns.max(1),
            shown_permille: None,
            enabled,
        }
    }

    /// Whether the bar draws.
    pub fn enabled(&self) -> bool {
        self.enabled
    }

    /// Records that `done_ns` of the run is through; redraws when the permille changes.
    pub fn set(&mut self, done_ns: u64) {
        if !self.enabled {
            return;
        }
        let permille = permille(done_ns, self.total_ns);
        if self.shown_permille == Some(permille) {
            return;
        }
        self.shown_permille = Some(permille);
        eprint!("\r{}", render(self.label, done_ns, self.total_ns));
    }

    /// Ends the bar: a final full line, then a line break.
    pub fn finish(&mut self) {
        if self.enabled && self.shown_permille.is_some() {
            self.shown_permille = None;
            eprintln!("\r{}", render(self.label, self.total_ns, self.total_ns));
        }
    }
}

fn permille(done_ns: u64, total_ns: u64) -> u64 {
    (u128::from(done_ns.min(total_ns)) * 1000 / u128::from(total_ns.max(1))) as u64
}

/// The bar's text: `label [=====>        ]  45.0%  27.0 / 60.0 s`.
pub fn render(label: &str, done_ns: u64, total_ns: u64) -> String {
    let pm = permille(done_ns, total_ns);
    let filled = (pm as usize * WIDTH) / 1000;
    let mut bar = "=".repeat(filled);
    if filled < WIDTH {
        bar.push('>');
        bar.push_str(&" ".repeat(WIDTH - filled - 1));
    }
    format!(
        "{label} [{bar}] {:5.1}%  {:.1} / {:.1} s",
        pm as f64 / 10.0,
        done_ns.min(total_ns) as f64 / 1e9,
        total_ns as f64 / 1e9
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_fill_percentage_and_seconds() {
        // 27 of 60 s: 450 permille, 450 * 30 / 1000 = 13.5 -> 13 cells filled, then '>'.
        let s = render("vigil sim", 27_000_000_000, 60_000_000_000);
        assert_eq!(
            s,
            format!(
                "vigil sim [{}>{}]  45.0%  27.0 / 60.0 s",
                "=".repeat(13),
                " ".repeat(16)
            )
        );
        // Done: every cell filled, no arrow; past the end is clamped.
        let s = render("r", 70, 60);
        assert!(
            s.starts_with(&format!("r [{}] 100.0%", "=".repeat(30))),
            "{s}"
        );
        let s = render("r", 0, 0);
        assert!(s.contains("[>"), "{s}");
    }

    #[test]
    fn draws_nothing_when_disabled_and_only_on_change() {
        let mut p = ProgressBar::new("x", 1000, false);
        p.set(500);
        assert_eq!(p.shown_permille, None);
        p.finish();
        let mut p = ProgressBar::new("x", 1000, true);
        p.set(1);
        assert_eq!(p.shown_permille, Some(1));
        // Same permille: no redraw state change.
        p.set(1);
        assert_eq!(p.shown_permille, Some(1));
        p.finish();
        assert_eq!(p.shown_permille, None);
    }
}
