//! `catflip optimize --whole --verify`: the whole-manoeuvre optimum and rapier's verification of
//! it, on any two-motor cat (the universal joint's two revolutes, the no-twist joint's ball joint;
//! equal or unequal halves).
//!
//! The verification is [`WholeReport::verify`]'s: rapier tracks the optimum's joint trajectory with its
//! motors, the step is halved until rapier's own error estimate meets `[rapier]`'s tolerances,
//! and the verdict compares the extrapolated twist, swing and peak torque with the exact engine's
//! numbers of the optimum ([`crate::engines::rapier::verify`]).

use std::fmt::Write as _;

use serde::Serialize;

use crate::engines::rapier::Verification;
use crate::measure::whole::WholeReport;
use crate::report::whole::verification_row_markdown;

/// The optimum with rapier's verification (none when there is no optimum to verify).
#[derive(Clone, Debug, Serialize)]
pub struct WholeCheck {
    /// The optimum, as `optimize --whole` reports it.
    #[serde(flatten)]
    pub report: WholeReport,
    /// Rapier's verification of the optimum.
    pub rapier: Option<Verification>,
}

impl WholeCheck {
    /// The optimum with its verification, once [`WholeReport::verify`] ran.
    pub fn new(report: WholeReport) -> WholeCheck {
        let rapier = report.verification().cloned();
        WholeCheck { report, rapier }
    }

    /// The optimum's report followed by the verification's section.
    pub fn to_markdown(&self) -> String {
        let mut s = self.report.to_markdown();
        let _ = writeln!(s, "\n## Rapier verification\n");
        match &self.rapier {
            None => {
                let _ = writeln!(s, "Not run: there is no optimum to verify.");
            }
            Some(v) => {
                let _ = writeln!(s, "rapier3d (f64) tracks the optimum's joint trajectory with its motors; the step is halved until rapier's own error estimate meets the `[rapier]` tolerances, and the extrapolated numbers are compared with the exact engine's.\n");
                let _ = writeln!(s, "```text\n{}```\n", v.to_text());
                if let Some(row) = verification_row_markdown(&self.report) {
                    let _ = write!(s, "{}{row}", crate::report::check::VERIFICATION_TABLE_HEADER);
                }
            }
        }
        s
    }
}
