//! `softgrip view --measure`: the viewer redraws continuously with the solver as fast as it goes,
//! then prints the frame intervals, the UI's own work per frame and the solver's speed, and
//! closes.

use softgrip_core::live::Frame;

/// Frame intervals and the UI's own work per frame (panels, drawing
/// built, GPU commands recorded), in seconds.
pub(crate) struct Measure {
    span: std::time::Duration,
    start: Option<std::time::Instant>,
    frames: Vec<f64>,
    work: Vec<f64>,
    done: bool,
}

impl Measure {
    /// Measures for `span` after a second of warm-up.
    pub(crate) fn new(span: std::time::Duration) -> Measure {
        Measure {
            span,
            start: None,
            frames: Vec::new(),
            work: Vec::new(),
            done: false,
        }
    }

    /// Prints the figures; true when the span is over.
    pub(crate) fn record(
        &mut self,
        interval: Option<f64>,
        work: f64,
        frame: Option<&Frame>,
    ) -> bool {
        if self.done {
            return true;
        }
        let start = *self.start.get_or_insert_with(std::time::Instant::now);
        // The first second is warm-up (shader compilation, first mesh).
        if start.elapsed().as_secs_f64() < 1.0 {
            return false;
        }
        if let Some(i) = interval {
            self.frames.push(i);
        }
        self.work.push(work);
        if start.elapsed() < self.span + std::time::Duration::from_secs(1) {
            return false;
        }
        let stats = |v: &mut Vec<f64>| {
            v.sort_by(f64::total_cmp);
            let mean = v.iter().sum::<f64>() / v.len().max(1) as f64;
            let at = |q: f64| {
                v.get(((v.len() as f64 - 1.0) * q).round() as usize)
                    .copied()
            };
            (mean, at(0.5).unwrap_or(0.0), at(0.95).unwrap_or(0.0))
        };
        let (mean, median, p95) = stats(&mut self.frames);
        let (wmean, wmedian, wp95) = stats(&mut self.work);
        let tets = frame
            .and_then(|f| f.model.as_ref())
            .map_or(0, |m| m.tets.len());
        println!(
            "viewer: {} frames, {tets} tetrahedra; frame interval mean {:.1} ms, median {:.1} ms, 95 % {:.1} ms ({:.1} frames/s); UI work per frame mean {:.1} ms, median {:.1} ms, 95 % {:.1} ms; solver {:.0} steps/s ({:.2} x real time, {:?})",
            self.frames.len(),
            1e3 * mean,
            1e3 * median,
            1e3 * p95,
            1.0 / mean.max(1e-9),
            1e3 * wmean,
            1e3 * wmedian,
            1e3 * wp95,
            frame.map_or(0.0, |f| f.steps_per_second),
            frame.map_or(0.0, |f| f.realtime_factor),
            frame.map(|f| f.run),
        );
        self.done = true;
        true
    }
}
