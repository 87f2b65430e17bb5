//! What the 3-D view draws instead of the live frame while a replayed recording is shown: the
//! sample's replayed state, its recorded and simulated markers, and a caption.

use std::sync::Arc;

use super::replayed::Replayed;
use crate::render::markers::MarkerPair;
use softgrip_core::model::Model;
use softgrip_core::state::State;

/// What the 3-D view draws instead of the live frame while the recording
/// is shown.
pub struct Overlay {
    /// The model the recording was replayed on.
    pub model: Arc<Model>,
    /// The replayed state at the sample shown.
    pub state: State,
    /// The sample's compared markers, recorded and simulated (m).
    pub markers: Vec<MarkerPair>,
    /// Residuals drawn this many times longer.
    pub exaggerate: f64,
    /// What is shown, for the view's caption.
    pub caption: String,
    /// Changes whenever what is drawn changes.
    pub key: OverlayKey,
}

/// The replay (its address), the sample and the exaggeration (`f64`
/// bits) an overlay shows.
pub type OverlayKey = (usize, usize, u64);

impl Overlay {
    /// `sample` of `replayed`, its residuals drawn `exaggerate` times
    /// longer; `None` if the replay has no state for it.
    pub(super) fn of(replayed: &Arc<Replayed>, sample: usize, exaggerate: f64) -> Option<Overlay> {
        let state = replayed.state(sample)?;
        let markers = replayed.markers(sample, &state);
        let n = replayed.recording.samples.len();
        Some(Overlay {
            model: Arc::clone(&replayed.model),
            state,
            markers,
            exaggerate,
            caption: format!(
                "recording, sample {}/{n}: {}{}",
                sample + 1,
                replayed.sample_label(sample),
                if exaggerate == 1.0 {
                    String::new()
                } else {
                    format!(", residuals drawn x{exaggerate:.0}")
                }
            ),
            key: (Arc::as_ptr(replayed) as usize, sample, exaggerate.to_bits()),
        })
    }
}
