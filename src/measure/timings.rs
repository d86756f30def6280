//! How long each stage of a run took: the wall-clock interval of every computation, from the
//! run's start, for `catflip run --timings` (issue 19, "measure each stage once").
//!
//! The stages overlap (they run in parallel, [`super::run::compute`]), so their times do not add up to
//! the run's: the table shows when each started and ended, and the run's critical path is the
//! chain that ends last. Times are wall clock on a machine shared with whatever else runs; they
//! are printed, never written into the results (which depend on the problem only).

use std::sync::Mutex;
use std::time::Instant;

/// One stage's interval, s from the run's start.
#[derive(Clone, Debug, PartialEq)]
pub struct StageTime {
    /// What was computed, in the report's words.
    pub name: String,
    /// Start, s from the run's start.
    pub start_s: f64,
    /// Duration, s.
    pub wall_s: f64,
}

/// Records stage intervals from any thread.
#[derive(Debug)]
pub struct Stopwatch {
    start: Instant,
    stages: Mutex<Vec<StageTime>>,
}

impl Stopwatch {
    /// A stopwatch started now.
    pub fn start() -> Self {
        Self { start: Instant::now(), stages: Mutex::new(Vec::new()) }
    }

    /// Runs `f` as the stage `name` and records its interval.
    pub fn time<T>(&self, name: impl Into<String>, f: impl FnOnce() -> T) -> T {
        let begin = Instant::now();
        let value = f();
        let stage = StageTime {
            name: name.into(),
            start_s: begin.duration_since(self.start).as_secs_f64(),
            wall_s: begin.elapsed().as_secs_f64(),
        };
        // A poisoned lock means another stage panicked; its own panic is the error to see.
        if let Ok(mut stages) = self.stages.lock() {
            stages.push(stage);
        }
        value
    }

    /// The stages recorded, in order of their start, and the whole run's time so far, s.
    pub fn finish(self) -> (Vec<StageTime>, f64) {
        let total = self.start.elapsed().as_secs_f64();
        let mut stages = self.stages.into_inner().unwrap_or_else(|poisoned| poisoned.into_inner());
        stages.sort_by(|a, b| a.start_s.total_cmp(&b.start_s));
        (stages, total)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stages_are_sorted_by_start_and_lie_within_the_run() {
        let clock = Stopwatch::start();
        let a = clock.time("first", || 1);
        clock.time("second", || std::thread::sleep(std::time::Duration::from_millis(2)));
        assert_eq!(a, 1, "the stage's value is returned");
        let (stages, total) = clock.finish();
        let names: Vec<_> = stages.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names, ["first", "second"]);
        assert!(stages[1].wall_s >= 0.002, "the sleep is inside the stage: {:?}", stages[1]);
        for s in &stages {
            assert!(s.start_s >= 0.0 && s.start_s + s.wall_s <= total, "{s:?} outside 0..{total}");
        }
        let shown = crate::report::run::timings_table(&stages, total);
        assert_eq!(shown.lines().count(), 4, "header, two stages, total:\n{shown}");
        assert!(shown.lines().last().is_some_and(|l| l.starts_with("run")), "{shown}");
    }
}
