//! `dampid identify`: a model file's job identified by the one pipeline
//! ([`crate::identify::identify`]), with the command line's options (accepting
//! transient windows, a bootstrap), and its outcome: the text report, the JSON document
//! and the HTML page, the same for a linear fit and for one with estimated parameters,
//! on records or on a stepped-sine table. The Python package's `identify_file` is this
//! command with another printer.

use std::fmt;
use std::path::Path;

use serde::Serialize;

use super::Outcome;
use crate::analysis::bootstrap::BootstrapSettings;
use crate::error::Result;
use crate::identify::{Equivalent, Identification, IdentifySettings, identify};
use crate::model_file::Job;
use crate::progress::Progress;
use crate::report::count;
use crate::report::html::HtmlReport;
use crate::report::provenance::Provenance;

/// What `dampid identify` takes besides the model file.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct IdentifyOptions {
    /// Accept windows that are not in steady state (a warning instead of an error),
    /// whatever `[identification]` says.
    pub accept_transient: bool,
    /// Fit input work that is negative beyond its noise
    /// ([`crate::regressor::passive`]), whatever `[identification]` says.
    pub accept_negative_work: bool,
    /// Percentile intervals from a bootstrap.
    pub bootstrap: Option<BootstrapSettings>,
    /// `--strict`: undetermined coefficients, accepted transients, a failed model check
    /// or an estimated parameter on its bound fail the command.
    pub strict: bool,
    /// The command line as the user typed it (for the report's provenance).
    pub command_line: String,
}

impl IdentifyOptions {
    /// The options as provenance rows (name, value), the command line first.
    pub fn provenance_rows(&self) -> Vec<(String, String)> {
        let given = |yes: bool, what: &str| {
            if yes {
                what.to_string()
            } else {
                "not given".to_string()
            }
        };
        vec![
            ("command line".to_string(), self.command_line.clone()),
            (
                "--accept-transient".to_string(),
                given(
                    self.accept_transient,
                    "given (accept_transient = true whatever [identification] says)",
                ),
            ),
            (
                "--accept-negative-work".to_string(),
                given(
                    self.accept_negative_work,
                    "given (accept_negative_work = true whatever [identification] says)",
                ),
            ),
            (
                "--bootstrap".to_string(),
                self.bootstrap.map_or("not given".to_string(), |b| {
                    format!(
                        "{} replicates, seed {}, {}% percentile intervals",
                        b.replicates,
                        b.seed,
                        100.0 * b.level
                    )
                }),
            ),
            ("--strict".to_string(), given(self.strict, "given")),
        ]
    }
}

impl IdentifyOptions {
    /// The settings `job` is identified with under these options.
    pub fn settings(&self, job: &Job) -> IdentifySettings {
        let mut settings = job.settings.clone();
        if let Some(steady) = &mut settings.steady_state {
            steady.accept_transient |= self.accept_transient;
        }
        settings.fit.accept_negative_work |= self.accept_negative_work;
        settings.bootstrap = self.bootstrap;
        settings
    }
}

/// Identifies `job` with `options`; `progress` counts bootstrap replicates.
pub fn run(job: &Job, options: &IdentifyOptions, progress: Progress<'_>) -> Result<Identification> {
    identify(&job.problem(), &options.settings(job), progress)
}

/// The outcome of `dampid identify`: a job and what identifying it found.
#[derive(Debug, Clone, Copy)]
pub struct Identified<'a> {
    /// The job.
    pub job: &'a Job,
    /// The options it ran with.
    pub options: &'a IdentifyOptions,
    /// What it found.
    pub identification: &'a Identification,
}

impl Identified<'_> {
    /// The HTML page of the outcome; `model_file` is the job's file (for the provenance:
    /// its text, its data files' SHA-256 and every setting in effect).
    pub fn html(&self, model_file: &Path) -> Result<String> {
        let provenance = self.job.provenance(
            model_file,
            &self.options.settings(self.job),
            &self.options.provenance_rows(),
        )?;
        self.html_with(Some(&provenance))
    }

    /// The HTML page with a given provenance (`None`: no provenance section).
    pub fn html_with(&self, provenance: Option<&Provenance>) -> Result<String> {
        let job = self.job;
        let found = self.identification;
        HtmlReport {
            title: &job.title,
            model: &found.model,
            source: job.problem().source(),
            regressor: &found.regressor,
            report: &found.report,
            truth: job.truth.as_deref(),
            pod: job.pod.as_ref(),
            steady: found.steady_state.as_deref(),
            equivalent: found.equivalent.as_ref().map(Equivalent::as_result),
            backbone: found.backbone.as_ref(),
            provenance,
            units: Some(&job.units),
        }
        .render()
    }
}

impl fmt::Display for Identified<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let job = self.job;
        let found = self.identification;
        let report = &found.report;
        let source = job.problem().source();
        writeln!(f, "{}", job.title)?;
        writeln!(
            f,
            "{}, {}",
            count(source.groups(), source.unit()),
            count(report.residuals.len(), "equation")
        )?;
        write!(f, "{}{report}", job.preamble(found.steady_state.as_deref()))?;
        if let Some(truth) = &job.truth {
            write!(f, "{}", report.against(truth))?;
        }
        match &found.equivalent {
            Some(Equivalent::Computed(e)) => write!(f, "{e}")?,
            Some(Equivalent::NotComputed { error }) => {
                writeln!(f, "equivalent damping not computed: {error}")?
            }
            None => {}
        }
        if let Some(backbone) = &found.backbone {
            write!(f, "{backbone}")?;
        }
        Ok(())
    }
}

impl Serialize for Identified<'_> {
    fn serialize<S: serde::Serializer>(
        &self,
        serializer: S,
    ) -> std::result::Result<S::Ok, S::Error> {
        let job = self.job;
        let found = self.identification;
        #[derive(Serialize)]
        struct Document<'a> {
            model: &'a str,
            report: &'a crate::report::FitReport,
            truth: Option<serde_json::Map<String, serde_json::Value>>,
            steady_state: &'a Option<std::sync::Arc<crate::prep::steady_state::SteadyStateReport>>,
            detected_periods: &'a [Option<crate::prep::period::PeriodEstimate>],
            pod: Option<Vec<crate::prep::pod::PodReport>>,
            equivalent_damping: &'a Option<Equivalent>,
            #[serde(skip_serializing_if = "Vec::is_empty")]
            free_decay: &'a Vec<crate::prep::free_decay::DecaySummary>,
            #[serde(skip_serializing_if = "Option::is_none")]
            backbone: &'a Option<crate::analysis::backbone::Backbone>,
        }
        Document {
            model: &job.title,
            report: &found.report,
            truth: job.truth.as_ref().map(|t| {
                t.iter()
                    .map(|(n, v)| (n.clone(), serde_json::json!(v)))
                    .collect()
            }),
            steady_state: &found.steady_state,
            detected_periods: &job.detected_periods,
            pod: job.pod.as_ref().map(|r| r.reports()),
            equivalent_damping: &found.equivalent,
            free_decay: &job.free_decay,
            backbone: &found.backbone,
        }
        .serialize(serializer)
    }
}

impl Outcome for Identified<'_> {
    fn strict_failures(&self) -> Vec<String> {
        self.identification.report.strict_failures()
    }

    fn trusted(&self) -> bool {
        self.identification.report.is_usable()
    }
}
