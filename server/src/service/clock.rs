//! The service's own clock: milliseconds since start, monotonic. It ages fleet objects and
//! nothing else; tracking runs on scan timestamps only.

use std::time::Instant;

/// Milliseconds since the service started.
#[derive(Clone, Copy, Debug)]
pub struct Clock {
    start: Instant,
}

impl Clock {
    /// A clock starting now.
    pub fn start() -> Self {
        Self {
            start: Instant::now(),
        }
    }

    /// Milliseconds since start.
    pub fn now_ms(&self) -> u64 {
        self.start.elapsed().as_millis() as u64
    }
}
