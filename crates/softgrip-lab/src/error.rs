//! Errors of the lab's sweeps, fits, diagnosis and proof. Each prints what the user reads (the
//! CLI's error line, the viewer's panel, a report's table): what went wrong and what to write
//! instead. Errors of other crates are wrapped in an `Arc` so that results holding them (a
//! sweep's points, a fit's trials, a diagnosis's candidates) can be cloned.

use std::path::PathBuf;
use std::sync::Arc;

use crate::recording::RecordingError;
use crate::synth::SynthError;
use softgrip_core::error::SimError;

/// Why a lab sweep, fit, diagnosis or proof could not run.
#[derive(Debug, Clone, thiserror::Error)]
pub enum LabError {
    /// What the user gave cannot be used: an unknown parameter, a value the scene file would
    /// reject, a malformed bound or sweep axis, or a scene that lacks what the task needs. The
    /// message names it and says what to write.
    #[error("{0}")]
    Input(String),

    /// A simulation failed (a cancelled one is [`LabError::Cancelled`]).
    #[error(transparent)]
    Sim(Arc<SimError>),

    /// A recording could not be read.
    #[error(transparent)]
    Recording(Arc<RecordingError>),

    /// A synthetic recording could not be made.
    #[error(transparent)]
    Synth(Arc<SynthError>),

    /// A file could not be written into the directory `dir`.
    #[error("{}: {source}", dir.display())]
    Write {
        /// The directory.
        dir: PathBuf,
        /// Why not.
        source: Arc<std::io::Error>,
    },

    /// A fit's starting point does not run.
    #[error("the starting point does not run: {0}")]
    FitStart(Box<LabError>),

    /// A diagnosis fit's start ran but gave no finite cost.
    #[error("the start failed")]
    StartFailed,

    /// Stopped through its `softgrip_core::cancel` token.
    #[error("cancelled")]
    Cancelled,
}

impl LabError {
    /// A [`LabError::Input`] saying `message`.
    pub fn input(message: impl Into<String>) -> LabError {
        LabError::Input(message.into())
    }
}

impl From<SimError> for LabError {
    fn from(e: SimError) -> LabError {
        match e {
            SimError::Cancelled => LabError::Cancelled,
            e => LabError::Sim(Arc::new(e)),
        }
    }
}

impl From<RecordingError> for LabError {
    fn from(e: RecordingError) -> LabError {
        LabError::Recording(Arc::new(e))
    }
}

impl From<SynthError> for LabError {
    fn from(e: SynthError) -> LabError {
        LabError::Synth(Arc::new(e))
    }
}

/// Equal when of the same kind and saying the same: the wrapped errors of other crates cannot be
/// compared otherwise.
impl PartialEq for LabError {
    fn eq(&self, other: &LabError) -> bool {
        use LabError::*;
        match (self, other) {
            (Input(a), Input(b)) => a == b,
            (FitStart(a), FitStart(b)) => a == b,
            (StartFailed, StartFailed) | (Cancelled, Cancelled) => true,
            (Sim(_), Sim(_))
            | (Recording(_), Recording(_))
            | (Synth(_), Synth(_))
            | (Write { .. }, Write { .. }) => self.to_string() == other.to_string(),
            _ => false,
        }
    }
}
