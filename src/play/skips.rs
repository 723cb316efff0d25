//! Rows skipped while playing, and why: each malformed row is named as it is met while there
//! are few, and the run ends with one line that counts them all by kind, so a file with a
//! million bad rows neither floods the terminal nor keeps a million messages.

/// How many malformed rows are named one by one before the rest are only counted.
pub const NAMED: usize = 10;

/// The skipped rows of one run.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Skips {
    untracked: usize,
    malformed: usize,
    last: Option<String>,
}

impl Skips {
    /// Counts a row the tracker marked untracked (`success` 0).
    pub fn untracked(&mut self) {
        self.untracked += 1;
    }

    /// Counts a malformed row (`SOURCE:LINE: why`); the line to print now, `None` once
    /// [`NAMED`] rows have been named (the rest appear in [`Skips::summary`]).
    pub fn malformed(&mut self, message: &str) -> Option<String> {
        self.malformed += 1;
        if self.malformed <= NAMED {
            Some(format!("{message} (row skipped)"))
        } else {
            self.last = Some(message.to_string());
            None
        }
    }

    /// Every row skipped.
    pub fn total(&self) -> usize {
        self.untracked + self.malformed
    }

    /// One line saying what was skipped and why, `None` when nothing was:
    /// `skipped 3 rows: 1 untracked (no face found, success 0), 2 malformed (named above)`.
    pub fn summary(&self) -> Option<String> {
        if self.total() == 0 {
            return None;
        }
        let mut parts = Vec::new();
        if self.untracked > 0 {
            parts.push(format!(
                "{} untracked (no face found, success 0)",
                self.untracked
            ));
        }
        if self.malformed > 0 {
            let named = self.malformed.min(NAMED);
            let mut part = format!("{} malformed ({named} named above", self.malformed);
            if let Some(last) = &self.last {
                part.push_str(&format!(
                    "; {} more not named, the last: {last}",
                    self.malformed - named
                ));
            }
            part.push(')');
            parts.push(part);
        }
        let rows = if self.total() == 1 { "row" } else { "rows" };
        Some(format!(
            "skipped {} {rows}: {}",
            self.total(),
            parts.join(", ")
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn few_rows_are_named_and_many_summarised() {
        let mut skips = Skips::default();
        assert_eq!(skips.summary(), None);
        skips.untracked();
        assert_eq!(
            skips.malformed("a.csv:3: 4 of 5 fields, the row is cut short"),
            Some("a.csv:3: 4 of 5 fields, the row is cut short (row skipped)".to_string())
        );
        assert_eq!(
            skips.summary().unwrap(),
            "skipped 2 rows: 1 untracked (no face found, success 0), 1 malformed (1 named above)"
        );
        for line in 4..4 + 2 * NAMED {
            skips.malformed(&format!("a.csv:{line}: bad"));
        }
        assert_eq!(
            skips.summary().unwrap(),
            format!(
                "skipped {} rows: 1 untracked (no face found, success 0), {} malformed ({NAMED} named above; {} more not named, the last: a.csv:{}: bad)",
                2 + 2 * NAMED,
                1 + 2 * NAMED,
                1 + NAMED,
                3 + 2 * NAMED
            )
        );
    }
}
