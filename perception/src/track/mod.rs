//! Frame-to-frame object tracking (the paper's Algorithm 1 and what a real tracker adds to it):
//! association by VFH tests, a motion EKF and a global assignment; oriented boxes completed
//! from partial views; confidence decay; training-free identification of objects versus
//! static structure.

pub mod arrivals;
pub mod assignment;
pub mod association;
pub mod box_fit;
pub mod car_peel;
pub mod classify;
pub mod confidence;
pub mod config;
pub mod dormant;
pub mod fragments;
pub mod ground;
pub mod motion;
mod movement;
pub mod observation;
mod parts;
pub mod person_split;
mod raster;
pub mod split;
pub mod standing_peel;
pub mod tracker;
pub mod views;
pub mod visibility;
pub mod votes;

pub use config::{AssociationMode, TrackConfig};
pub use ground::Ground;
pub use split::Splitter;
pub use tracker::{ClusterInput, PredictedBox, ScanContext, Track, Tracker};
pub use views::{RecentViews, View};
pub use visibility::RangeImage;
