//! The JSON bodies of trackd's REST API, shared by the server and this client.
//!
//! Positions are metres in the fleet's world frame: x east, y north, z up of the fleet's
//! geodetic origin (KITTI's Mercator convention at the origin's scale). Angles are radians,
//! velocities m/s, durations milliseconds.

use serde::{Deserialize, Serialize};

/// Media type of protobuf bodies (`trackd_proto::Scan`, `trackd_proto::SuperFrame`).
pub const PROTOBUF: &str = "application/x-protobuf";
/// Media type of a raw KITTI `.bin` scan: packed little-endian f32 x, y, z, intensity.
pub const KITTI_BIN: &str = "application/x-kitti-bin";
/// Media type of a PCD scan (ASCII, binary or binary_compressed).
pub const PCD: &str = "application/x-pcd";
/// Media type of an OctoMap binary (`.bt`) file.
pub const OCTOMAP_BT: &str = "application/x-octomap-bt";

/// Header carrying a raw scan's timestamp (seconds) when not in the query.
pub const HEADER_TIMESTAMP: &str = "x-trackd-timestamp";
/// Header carrying a raw scan's pose `x,y,z,qw,qx,qy,qz` when not in the query.
pub const HEADER_POSE: &str = "x-trackd-pose";
/// Header carrying a raw scan's OXTS packet (30 comma-separated values) when not in the query.
pub const HEADER_OXTS: &str = "x-trackd-oxts";

/// One tracked object in the world frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct Track {
    /// Stable identifier of the track on this vehicle.
    pub id: u64,
    /// Object class: `unknown`, `car`, `cyclist`, `pedestrian`, `other_movable`.
    pub class: String,
    /// Box centre, east (m).
    pub x: f64,
    /// Box centre, north (m).
    pub y: f64,
    /// Box centre, up (m).
    pub z: f64,
    /// Box length along its heading (m).
    pub l: f64,
    /// Box width (m).
    pub w: f64,
    /// Box height (m).
    pub h: f64,
    /// Heading about z (rad, 0 = east).
    pub yaw: f64,
    /// Velocity east (m/s).
    pub vx: f64,
    /// Velocity north (m/s).
    pub vy: f64,
    /// Tracking confidence in [0, 1].
    pub confidence: f32,
    /// Frames since birth.
    pub age: u32,
    /// Frames in which the track was matched.
    pub hits: u32,
}

/// The tracks after one processed frame (also the payload of each `/v1/stream` event).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct Tracks {
    /// The vehicle that tracked them.
    pub vehicle: String,
    /// Index of the frame in the vehicle's pipeline (0-based); `None` before the first frame.
    pub frame: Option<u64>,
    /// The frame's scan timestamp (seconds).
    pub timestamp: Option<f64>,
    /// `world` when the scan's pose was known, `sensor` otherwise.
    pub tracking_frame: Option<String>,
    /// Confirmed tracks.
    pub tracks: Vec<Track>,
}

/// Per-stage wall time of one frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct StageTime {
    /// Stage name.
    pub stage: String,
    /// Milliseconds.
    pub ms: f64,
}

/// Answer to `POST /v1/scans`: the scan was processed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct ScanProcessed {
    /// The id the service gave the upload (order of acceptance).
    pub scan_id: u64,
    /// Index of the frame in the pipeline.
    pub frame: u64,
    /// Points in the scan.
    pub points: usize,
    /// Per-stage wall time.
    pub timings: Vec<StageTime>,
    /// Whether this frame triggered a super frame to the fleet.
    pub superframe: bool,
    /// The tracks after this frame.
    pub tracks: Tracks,
}

/// Answer to `POST /v1/scans?async=true` (202): the scan was queued.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct ScanQueued {
    /// The id the service gave the upload (order of acceptance).
    pub scan_id: u64,
    /// Scans waiting in the queue, this one included.
    pub queue_depth: usize,
}

/// One position of a track's history.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct TrackPoint {
    /// Frame index.
    pub frame: u64,
    /// Scan timestamp (seconds).
    pub timestamp: f64,
    /// East (m).
    pub x: f64,
    /// North (m).
    pub y: f64,
    /// Up (m).
    pub z: f64,
}

/// Answer to `GET /v1/tracks/{id}`: the track now (if still tracked) and where it has been.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct TrackHistory {
    /// Track id.
    pub id: u64,
    /// The track after the latest frame, if it is still confirmed.
    pub current: Option<Track>,
    /// Positions, oldest first (bounded; the oldest are forgotten first).
    pub history: Vec<TrackPoint>,
}

/// What this service knows of one vehicle of the fleet.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct VehicleStatus {
    /// Vehicle id.
    pub id: String,
    /// Whether its Zenoh liveliness token is present.
    pub alive: bool,
    /// Milliseconds since its last super frame arrived; `None`: none yet.
    pub last_seen_ms: Option<u64>,
    /// Sequence number of its last super frame.
    pub sequence: Option<u64>,
    /// Scan timestamp of its last super frame (its clock, seconds).
    pub timestamp: Option<f64>,
    /// Publish → receive delay of its last super frame as measured by Zenoh timestamps
    /// (ms; only meaningful when clocks agree, as on one machine).
    pub lag_ms: Option<f64>,
    /// Objects in its last super frame.
    pub objects: usize,
    /// Super frames received from it.
    pub superframes: u64,
}

/// Answer to `GET /v1/fleet`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct Fleet {
    /// This vehicle's id.
    pub vehicle: String,
    /// The fleet's geodetic origin `[lat, lon, alt]`, if configured.
    pub origin: Option<[f64; 3]>,
    /// Remote vehicles heard of (liveliness or super frames), sorted by id.
    pub vehicles: Vec<VehicleStatus>,
}

/// One object of the fused fleet view.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct FusedObject {
    /// `<vehicle>/<track id>` of the observation it is anchored on (this vehicle's own track
    /// when it sees the object).
    pub id: String,
    /// Object class.
    pub class: String,
    /// Box centre, east of the fleet origin (m).
    pub x: f64,
    /// Box centre, north of the fleet origin (m).
    pub y: f64,
    /// Box centre, up from the fleet origin (m).
    pub z: f64,
    /// Box length (m).
    pub l: f64,
    /// Box width (m).
    pub w: f64,
    /// Box height (m).
    pub h: f64,
    /// Heading (rad, 0 = east).
    pub yaw: f64,
    /// Velocity east (m/s).
    pub vx: f64,
    /// Velocity north (m/s).
    pub vy: f64,
    /// Combined confidence: 1 − Π(1 − cᵢ) over the sources.
    pub confidence: f32,
    /// Vehicles that see it, this one first when it does.
    pub sources: Vec<String>,
    /// Milliseconds since its freshest observation arrived.
    pub age_ms: u64,
}

/// Answer to `GET /v1/fleet/objects`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct FusedObjects {
    /// The fused world view.
    pub objects: Vec<FusedObject>,
}

/// Answer to `GET /healthz`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct Health {
    /// `ok`.
    pub status: String,
    /// This vehicle's id.
    pub vehicle: String,
    /// Frames processed.
    pub frames: u64,
    /// Scans waiting in the queue.
    pub queue_depth: usize,
    /// Whether the Zenoh session is up.
    pub zenoh: bool,
}

/// A super frame as JSON (`GET /v1/superframes/latest` with `Accept: application/json`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct SuperFrameView {
    /// The vehicle that sent it.
    pub vehicle: String,
    /// Its sequence number.
    pub sequence: u64,
    /// Scan timestamp it was made at (seconds).
    pub timestamp: f64,
    /// The geodetic origin `[lat, lon, alt]` of its world frame.
    pub origin: Option<[f64; 3]>,
    /// The sender's sensor pose `[x, y, z, qw, qx, qy, qz]` in that frame.
    pub ego_pose: Option<[f64; 7]>,
    /// Its objects.
    pub objects: Vec<Track>,
}

/// A bird's-eye-view occupancy grid around the vehicle (`GET /v1/occupancy?format=grid`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct BevGrid {
    /// East of the grid's first column edge (m).
    pub min_x: f64,
    /// North of the grid's first row edge (m).
    pub min_y: f64,
    /// Cell edge (m).
    pub cell: f64,
    /// Cells per row (along x).
    pub width: usize,
    /// Rows (along y).
    pub height: usize,
    /// `width × height` cells, row-major from (`min_x`, `min_y`): 0 unknown, 1 free, 2 occupied.
    pub cells: Vec<u8>,
}

/// Body of every error answer.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct ApiError {
    /// What went wrong, for a person.
    pub error: String,
}
