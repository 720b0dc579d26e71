//! How often the simulation's snapshots repaint the window: at most every
//! three frame costs, and on a software rasteriser (a machine without a
//! GPU, where a 1366 × 768 frame measured ~90 ms of its threads' CPU, done
//! after eframe's own frame time is taken) at most four times a second, so
//! drawing keeps to about a third of the CPU and tracing has the rest.
//! Input repaints at once, as egui always does.

use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Shortest interval between snapshot repaints: 30 per second.
const MIN_INTERVAL: Duration = Duration::from_millis(33);
/// Longest: the view still moves twice a second however slow a frame is.
const MAX_INTERVAL: Duration = Duration::from_millis(500);
/// Repaint interval over the cost of one frame.
const INTERVALS_PER_FRAME_COST: u32 = 3;

/// Shortest interval on a software rasteriser.
pub const SOFTWARE_RASTERISER_INTERVAL: Duration = Duration::from_millis(250);

#[derive(Debug)]
struct Pace {
    last_repaint: Option<Instant>,
    interval: Duration,
    /// The shortest interval allowed on this renderer.
    floor: Duration,
}

/// Shared by the UI (which reports frame costs) and the simulation's
/// worker (which asks for repaints).
#[derive(Debug)]
pub struct RepaintPacer {
    pace: Mutex<Pace>,
}

impl Default for RepaintPacer {
    fn default() -> Self {
        RepaintPacer {
            pace: Mutex::new(Pace {
                last_repaint: None,
                interval: MIN_INTERVAL,
                floor: MIN_INTERVAL,
            }),
        }
    }
}

impl RepaintPacer {
    /// Draws on a software rasteriser: at most every
    /// [`SOFTWARE_RASTERISER_INTERVAL`].
    pub fn software_rasteriser(&self) {
        if let Ok(mut pace) = self.pace.lock() {
            pace.floor = SOFTWARE_RASTERISER_INTERVAL;
            pace.interval = pace.interval.max(pace.floor);
        }
    }

    /// The cost of the last frame (ui, tessellation and paint), as eframe
    /// measures it.
    pub fn frame_cost(&self, seconds: f32) {
        if !(seconds.is_finite() && seconds >= 0.0) {
            return;
        }
        let cost = Duration::from_secs_f32(seconds);
        if let Ok(mut pace) = self.pace.lock() {
            // Smoothed, so one slow frame does not halve the refresh.
            let target = (cost * INTERVALS_PER_FRAME_COST).clamp(pace.floor, MAX_INTERVAL);
            pace.interval = (pace.interval * 3 + target) / 4;
        }
    }

    /// The interval snapshot repaints keep now.
    pub fn interval(&self) -> Duration {
        self.pace.lock().map_or(MIN_INTERVAL, |p| p.interval)
    }

    /// How long the repaint for a snapshot arriving `now` should wait. A
    /// repaint already due later shows this snapshot too (every frame
    /// draws the newest): it is not pushed back, or snapshots arriving
    /// faster than the pace would put each repaint an interval later than
    /// the one before (1.4 s between frames after a drag's release).
    pub fn delay(&self, now: Instant) -> Duration {
        let Ok(mut pace) = self.pace.lock() else {
            return Duration::ZERO;
        };
        let due = match pace.last_repaint {
            None => now,
            Some(scheduled) if scheduled > now => scheduled,
            Some(last) => (last + pace.interval).max(now),
        };
        pace.last_repaint = Some(due);
        due - now
    }

    /// The next snapshot repaints at once: the first preview of an edit
    /// waits for no pace.
    pub fn reset(&self) {
        if let Ok(mut pace) = self.pace.lock() {
            pace.last_repaint = None;
        }
    }

    /// Asks `ctx` to repaint when the pace allows.
    pub fn request(&self, ctx: &egui::Context) {
        let delay = self.delay(Instant::now());
        if delay.is_zero() {
            ctx.request_repaint();
        } else {
            ctx.request_repaint_after(delay);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn snapshots_repaint_at_once_then_at_the_pace_of_three_frame_costs() {
        let pacer = RepaintPacer::default();
        let t0 = Instant::now();
        assert_eq!(pacer.delay(t0), Duration::ZERO);
        // A burst of snapshots is shown by one repaint an interval later,
        // not dropped, and not spread over later ones.
        assert_eq!(pacer.delay(t0), MIN_INTERVAL);
        assert_eq!(
            pacer.delay(t0 + Duration::from_millis(10)),
            MIN_INTERVAL - Duration::from_millis(10)
        );
        // Once that repaint is past, the next comes an interval after it.
        assert_eq!(
            pacer.delay(t0 + MIN_INTERVAL + Duration::from_millis(5)),
            MIN_INTERVAL - Duration::from_millis(5)
        );
        // Slow frames (100 ms) lengthen the interval towards 300 ms.
        for _ in 0..40 {
            pacer.frame_cost(0.1);
        }
        let interval = pacer.interval();
        assert!((interval.as_secs_f64() - 0.3).abs() < 0.005, "{interval:?}");
        // Never past the bounds.
        for _ in 0..40 {
            pacer.frame_cost(10.0);
        }
        assert!(pacer.interval() <= MAX_INTERVAL);
        pacer.frame_cost(f32::NAN);
        assert!(pacer.interval() <= MAX_INTERVAL);
    }

    /// Snapshots every 55 ms against a 250 ms pace for 5 s: a repaint
    /// every 250 ms throughout, never drifting later.
    #[test]
    fn a_stream_of_snapshots_faster_than_the_pace_repaints_at_the_pace() {
        let pacer = RepaintPacer::default();
        pacer.software_rasteriser();
        let t0 = Instant::now();
        let mut repaints = std::collections::BTreeSet::new();
        for k in 0..91 {
            let now = t0 + Duration::from_millis(55 * k);
            let delay = pacer.delay(now);
            assert!(delay <= SOFTWARE_RASTERISER_INTERVAL, "{k}: {delay:?}");
            repaints.insert(now + delay);
        }
        // 5 s at one repaint per 250 ms, the first at once.
        assert_eq!(repaints.len(), 21, "{repaints:?}");
    }

    #[test]
    fn a_software_rasteriser_repaints_at_most_four_times_a_second() {
        let pacer = RepaintPacer::default();
        pacer.software_rasteriser();
        for _ in 0..40 {
            pacer.frame_cost(0.002);
        }
        assert_eq!(pacer.interval(), SOFTWARE_RASTERISER_INTERVAL);
        let t0 = Instant::now();
        assert_eq!(pacer.delay(t0), Duration::ZERO);
        assert_eq!(pacer.delay(t0), SOFTWARE_RASTERISER_INTERVAL);
        // After an edit the first snapshot waits for nothing.
        pacer.reset();
        assert_eq!(pacer.delay(t0), Duration::ZERO);
    }
}
