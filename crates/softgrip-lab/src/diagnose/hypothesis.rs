//! A candidate tried: its fit, its score against the model it was added to, and whether its
//! evidence names its effect.

use super::model_fit::ModelFit;
use super::statistics::{BIC_THRESHOLD, MIN_EXPLAINED, vuong_threshold};
use crate::error::LabError;

/// A candidate tried.
#[derive(Debug, Clone)]
pub struct Hypothesis {
    /// The effect's catalogue name (`table-friction`, ...).
    pub effect: &'static str,
    /// Which variant (the region's place, the stiffening's form); empty for an effect with one.
    pub variant: String,
    /// The model with the candidate, fitted; or why its fit failed.
    pub fit: Result<ModelFit, LabError>,
    /// BIC against the model it was added to (negative: better).
    pub score: f64,
    /// Share of the weighted residual sum of squares it removed.
    pub explained: f64,
    /// The search's round it was fitted in, from 0.
    pub round: usize,
    /// Vuong's statistic against the best candidate of another effect in
    /// the same round (positive: this one fits closer) or, when no other
    /// effect was fitted in its round, against the model it was added to
    /// (`against_model`); None when the fit failed.
    pub vuong: Option<f64>,
    /// `vuong` is against the model without the effect: the round had no
    /// rival (BIC and the share alone would let form error through: with
    /// E's range given, two load losses took a wrong table friction in
    /// round 2 that way).
    pub against_model: bool,
    /// The independent tests its effect's candidates in its round (the four halves of a region,
    /// two forms of stiffening) count as ([`super::statistics::effective_tests`]): it must beat its rival by
    /// [`vuong_threshold`] of them.
    pub tests: f64,
    /// Wall-clock seconds its fit took (reported, never decided on).
    pub seconds: f64,
}

impl Hypothesis {
    /// What `vuong` compares it with, in words.
    pub fn rival_text(&self) -> &'static str {
        if self.against_model {
            "the model without it"
        } else {
            "the best other effect"
        }
    }

    /// Its Vuong z for tables: "+2.31", "+2.31 (against the model without
    /// it)", or "-".
    pub fn z_text(&self) -> String {
        match self.vuong {
            Some(z) if self.against_model => format!("{z:+.2} (against {})", self.rival_text()),
            Some(z) => format!("{z:+.2}"),
            None => "-".into(),
        }
    }
}

/// Is a candidate's evidence enough to name its effect?
pub fn accepted(h: &Hypothesis) -> bool {
    h.score < -BIC_THRESHOLD
        && h.explained >= MIN_EXPLAINED
        // Against the best other effect or, with none fitted in its
        // round, against the model without it.
        && h.vuong.is_some_and(|z| z >= vuong_threshold(h.tests))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A candidate with no other effect beside it in its round is named
    /// only when it also fits closer than the model without it by Vuong's
    /// z: BIC and the share alone let form error through (the load losses'
    /// round 2 with E's range given: -12 / 11 % and -13 / 12 % for a wrong
    /// table friction).
    #[test]
    fn a_lone_candidate_needs_vuongs_test_against_the_model_without_it() {
        let mut lone = tried("table-friction", -13.0, 0.12, 1.5);
        lone.against_model = true;
        assert!(!accepted(&lone), "z 1.5 against the model: not named");
        assert_eq!(lone.z_text(), "+1.50 (against the model without it)");
        lone.vuong = Some(2.5);
        assert!(accepted(&lone), "z 2.5: named");
        // BIC and the share still gate it.
        lone.score = -9.0;
        assert!(!accepted(&lone));
        // A failed fit (no z at all) is never named.
        let mut failed = tried("load-loss", -50.0, 0.5, 0.0);
        failed.vuong = None;
        assert!(!accepted(&failed));
        assert_eq!(failed.z_text(), "-");
        assert_eq!(tried("load-loss", -50.0, 0.5, 3.0).z_text(), "+3.00");
    }

    pub(crate) fn tried(
        effect: &'static str,
        score: f64,
        explained: f64,
        vuong: f64,
    ) -> Hypothesis {
        Hypothesis {
            effect,
            variant: String::new(),
            fit: Err(LabError::input("not run")),
            score,
            explained,
            round: 0,
            vuong: Some(vuong),
            against_model: false,
            tests: 1.0,
            seconds: 0.0,
        }
    }
}
