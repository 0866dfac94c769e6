//! The range images of the last scans, each with the sensor pose it was taken from: what the
//! sensor saw a moment ago along each direction. An object that now stands where the laser
//! passed freely then has moved there: it came nearer, or follows the vehicle, cases in which
//! the place it left stays hidden behind it.

use std::collections::VecDeque;

use nalgebra::Isometry3;

use super::visibility::RangeImage;

/// One scan's range image and where it was taken.
#[derive(Clone, Debug)]
pub struct View {
    /// Scan time, seconds.
    pub timestamp: f64,
    /// Pose of the sensor in the world frame.
    pub pose: Isometry3<f64>,
    /// What the scan saw, in its sensor frame.
    pub image: RangeImage,
}

/// The views of the scans of the last `keep` seconds, oldest first.
#[derive(Clone, Debug)]
pub struct RecentViews {
    views: VecDeque<View>,
    keep: f64,
}

impl RecentViews {
    /// An empty history that keeps views for `keep` seconds.
    pub fn new(keep: f64) -> Self {
        Self {
            views: VecDeque::new(),
            keep,
        }
    }

    /// An image buffer for the scan at `timestamp`: the oldest view's once it is older than
    /// the history keeps (its allocation is reused), else a new one.
    pub fn take_buffer(&mut self, timestamp: f64) -> RangeImage {
        match self.views.front() {
            Some(oldest) if self.expired(oldest, timestamp) => {
                self.views.pop_front().map(|v| v.image).unwrap_or_default()
            }
            _ => RangeImage::default(),
        }
    }

    /// Adds the newest scan's view and forgets views older than the history keeps.
    pub fn push(&mut self, view: View) {
        while self
            .views
            .front()
            .is_some_and(|oldest| self.expired(oldest, view.timestamp))
        {
            self.views.pop_front();
        }
        self.views.push_back(view);
    }

    /// Whether `view` is older than the history keeps at `timestamp`.
    fn expired(&self, view: &View, timestamp: f64) -> bool {
        timestamp - view.timestamp > self.keep
    }

    /// Forgets every view (the world frame is lost).
    pub fn clear(&mut self) {
        self.views.clear();
    }

    /// The newest view.
    pub fn latest(&self) -> Option<&View> {
        self.views.back()
    }

    /// The newest view taken at least `age` seconds before `timestamp`, if one is kept.
    pub fn before(&self, timestamp: f64, age: f64) -> Option<&View> {
        self.views
            .iter()
            .rev()
            .find(|v| v.timestamp <= timestamp - age)
    }

    /// The view of the scan taken at `timestamp`, if still kept.
    pub fn at(&self, timestamp: f64) -> Option<&View> {
        self.views.iter().rev().find(|v| v.timestamp == timestamp)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn view(timestamp: f64) -> View {
        View {
            timestamp,
            pose: Isometry3::identity(),
            image: RangeImage::default(),
        }
    }

    #[test]
    fn keeps_the_views_of_the_last_seconds_and_finds_them_by_time() {
        let mut views = RecentViews::new(1.0);
        for k in 0..20 {
            let t = f64::from(k) / 10.0;
            let _buffer = views.take_buffer(t);
            views.push(view(t));
        }
        let latest = views.latest().map(|v| v.timestamp);
        assert_eq!(latest, Some(1.9));
        assert!(views.at(1.0).is_some());
        assert!(views.at(0.8).is_none(), "older than a second");
        assert!(views.at(1.05).is_none(), "no scan then");
        views.clear();
        assert!(views.latest().is_none());
    }
}
