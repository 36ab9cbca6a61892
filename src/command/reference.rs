//! `dampid reference four-mass`: every case of the paper's section 2.2 simulated and
//! identified, against the paper's figures ([`crate::reference::FourMassSummary`]).

use std::fmt;

use serde::Serialize;

use super::Outcome;
use crate::error::Result;
use crate::prep::quadrature::Quadrature;
use crate::reference::FourMassSummary;

/// The four-mass reference study.
#[derive(Debug, Clone)]
pub struct Reference(pub FourMassSummary);

/// Runs the four-mass study with `quadrature`.
pub fn four_mass(quadrature: Quadrature) -> Result<Reference> {
    FourMassSummary::run(quadrature).map(Reference)
}

impl fmt::Display for Reference {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.0)
    }
}

impl Serialize for Reference {
    fn serialize<S: serde::Serializer>(
        &self,
        serializer: S,
    ) -> std::result::Result<S::Ok, S::Error> {
        self.0.to_json().serialize(serializer)
    }
}

impl Outcome for Reference {
    fn trusted(&self) -> bool {
        self.0.all_pass()
    }
}
