//! The pipeline's and the fusion's types as the API's JSON types.

use trackd_client::api;
use trackd_perception::{
    FrameOutput, TrackState, fleet::FusedObject, pipeline::TrackingFrame, wire::track_from_proto,
};
use trackd_proto::SuperFrame;

/// A track as JSON.
pub fn track(t: &TrackState) -> api::Track {
    api::Track {
        id: t.id,
        class: t.class.as_str().to_string(),
        x: t.center.x,
        y: t.center.y,
        z: t.center.z,
        l: t.size.x,
        w: t.size.y,
        h: t.size.z,
        yaw: t.yaw,
        vx: t.velocity.x,
        vy: t.velocity.y,
        confidence: t.confidence,
        age: t.age,
        hits: t.hits,
    }
}

/// The tracks of a frame as JSON.
pub fn tracks(vehicle: &str, out: &FrameOutput) -> api::Tracks {
    api::Tracks {
        vehicle: vehicle.to_string(),
        frame: Some(out.index),
        timestamp: Some(out.timestamp),
        tracking_frame: Some(
            match out.tracking_frame {
                TrackingFrame::World => "world",
                TrackingFrame::Sensor => "sensor",
            }
            .to_string(),
        ),
        tracks: out.tracks.iter().map(track).collect(),
    }
}

/// A fused object as JSON.
pub fn fused(o: &FusedObject) -> api::FusedObject {
    api::FusedObject {
        id: format!("{}/{}", o.anchor.0, o.anchor.1),
        class: o.class.as_str().to_string(),
        x: o.center.x,
        y: o.center.y,
        z: o.center.z,
        l: o.size.x,
        w: o.size.y,
        h: o.size.z,
        yaw: o.yaw,
        vx: o.velocity.x,
        vy: o.velocity.y,
        confidence: o.confidence,
        sources: o.sources.clone(),
        age_ms: o.age_ms,
    }
}

/// A super frame as JSON (objects that fail validation are left out).
pub fn superframe(sf: &SuperFrame) -> api::SuperFrameView {
    api::SuperFrameView {
        vehicle: sf.vehicle_id.clone(),
        sequence: sf.sequence,
        timestamp: sf.timestamp,
        origin: sf.origin.as_ref().map(|o| [o.lat, o.lon, o.alt]),
        ego_pose: sf
            .ego_pose
            .as_ref()
            .map(|p| [p.x, p.y, p.z, p.qw, p.qx, p.qy, p.qz]),
        objects: sf
            .objects
            .iter()
            .filter_map(|o| track_from_proto(o).ok())
            .map(|t| track(&t))
            .collect(),
    }
}
