//! Conversions between the pipeline's types and the protobuf messages vehicles exchange,
//! validating what comes in: a rogue message becomes a typed error, never a panic.

use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion, Vector2, Vector3};
use thiserror::Error;
use trackd_proto as proto;

use crate::{ObjectClass, Point, TrackState, geo::GeoOrigin};

/// Why a received message cannot be used.
#[derive(Debug, Error, PartialEq)]
pub enum WireError {
    /// A field the message needs is absent.
    #[error("missing field `{0}`")]
    Missing(&'static str),
    /// A number is NaN or infinite.
    #[error("non-finite value in `{0}`")]
    NonFinite(&'static str),
    /// The quaternion is far from unit length.
    #[error("pose quaternion is not a rotation (norm {0})")]
    NotARotation(f64),
    /// A packed point buffer's length is not a whole number of points.
    #[error("packed points: {len} bytes is not a multiple of {stride}")]
    PackedLength {
        /// Bytes received.
        len: usize,
        /// Bytes per point.
        stride: usize,
    },
    /// A value is outside its valid range.
    #[error("`{field}` out of range: {value}")]
    OutOfRange {
        /// The field.
        field: &'static str,
        /// The value received.
        value: f64,
    },
}

/// A pose as its message.
pub fn pose_to_proto(pose: &Isometry3<f64>) -> proto::Pose {
    let t = pose.translation.vector;
    let q = pose.rotation.quaternion();
    proto::Pose {
        x: t.x,
        y: t.y,
        z: t.z,
        qw: q.w,
        qx: q.i,
        qy: q.j,
        qz: q.k,
    }
}

/// A pose from its message; the quaternion must be (nearly) unit length.
pub fn pose_from_proto(p: &proto::Pose) -> Result<Isometry3<f64>, WireError> {
    let values = [p.x, p.y, p.z, p.qw, p.qx, p.qy, p.qz];
    if values.iter().any(|v| !v.is_finite()) {
        return Err(WireError::NonFinite("pose"));
    }
    let q = Quaternion::new(p.qw, p.qx, p.qy, p.qz);
    let norm = q.norm();
    if (norm - 1.0).abs() > 1e-3 {
        return Err(WireError::NotARotation(norm));
    }
    Ok(Isometry3::from_parts(
        Translation3::new(p.x, p.y, p.z),
        UnitQuaternion::from_quaternion(q),
    ))
}

/// A geodetic origin as its message.
pub fn origin_to_proto(o: &GeoOrigin) -> proto::GeoPoint {
    proto::GeoPoint {
        lat: o.lat,
        lon: o.lon,
        alt: o.alt,
    }
}

/// A geodetic origin from its message (latitude within ±85°, longitude within ±180°).
pub fn origin_from_proto(g: &proto::GeoPoint) -> Result<GeoOrigin, WireError> {
    if ![g.lat, g.lon, g.alt].iter().all(|v| v.is_finite()) {
        return Err(WireError::NonFinite("origin"));
    }
    if g.lat.abs() > 85.0 {
        return Err(WireError::OutOfRange {
            field: "origin.lat",
            value: g.lat,
        });
    }
    if g.lon.abs() > 180.0 {
        return Err(WireError::OutOfRange {
            field: "origin.lon",
            value: g.lon,
        });
    }
    Ok(GeoOrigin::new(g.lat, g.lon, g.alt))
}

/// A class as its message enum.
pub fn class_to_proto(c: ObjectClass) -> proto::ObjectClass {
    match c {
        ObjectClass::Unknown => proto::ObjectClass::Unknown,
        ObjectClass::Car => proto::ObjectClass::Car,
        ObjectClass::Cyclist => proto::ObjectClass::Cyclist,
        ObjectClass::Pedestrian => proto::ObjectClass::Pedestrian,
        ObjectClass::OtherMovable => proto::ObjectClass::OtherMovable,
    }
}

/// A class from its message enum value (unknown values read as `Unknown`).
pub fn class_from_proto(value: i32) -> ObjectClass {
    match proto::ObjectClass::try_from(value) {
        Ok(proto::ObjectClass::Car) => ObjectClass::Car,
        Ok(proto::ObjectClass::Cyclist) => ObjectClass::Cyclist,
        Ok(proto::ObjectClass::Pedestrian) => ObjectClass::Pedestrian,
        Ok(proto::ObjectClass::OtherMovable) => ObjectClass::OtherMovable,
        Ok(proto::ObjectClass::Unknown) | Err(_) => ObjectClass::Unknown,
    }
}

/// A track as a super frame object (box and velocity in the world frame), with its motion
/// covariance, VFH and packed world points.
pub fn track_to_proto(
    track: &TrackState,
    covariance: &[f64; 36],
    vfh: &[f32],
    packed_points: Vec<u8>,
) -> proto::TrackedObject {
    proto::TrackedObject {
        id: track.id,
        class: class_to_proto(track.class).into(),
        r#box: Some(proto::Box3 {
            x: track.center.x,
            y: track.center.y,
            z: track.center.z,
            l: track.size.x,
            w: track.size.y,
            h: track.size.z,
            yaw: track.yaw,
        }),
        vx: track.velocity.x,
        vy: track.velocity.y,
        covariance: covariance.to_vec(),
        confidence: track.confidence,
        vfh: vfh.to_vec(),
        points: packed_points,
        age: track.age,
        hits: track.hits,
    }
}

/// A received object as a track state (world frame); rejects missing boxes, non-finite
/// numbers, negative sizes and confidences outside [0, 1].
pub fn track_from_proto(o: &proto::TrackedObject) -> Result<TrackState, WireError> {
    let b = o.r#box.as_ref().ok_or(WireError::Missing("box"))?;
    let values = [
        b.x,
        b.y,
        b.z,
        b.l,
        b.w,
        b.h,
        b.yaw,
        o.vx,
        o.vy,
        f64::from(o.confidence),
    ];
    if values.iter().any(|v| !v.is_finite()) {
        return Err(WireError::NonFinite("object"));
    }
    for (field, value) in [("box.l", b.l), ("box.w", b.w), ("box.h", b.h)] {
        if !(0.0..=100.0).contains(&value) {
            return Err(WireError::OutOfRange { field, value });
        }
    }
    if !(0.0..=1.0).contains(&o.confidence) {
        return Err(WireError::OutOfRange {
            field: "confidence",
            value: f64::from(o.confidence),
        });
    }
    Ok(TrackState {
        id: o.id,
        class: class_from_proto(o.class),
        center: Vector3::new(b.x, b.y, b.z),
        size: Vector3::new(b.l, b.w, b.h),
        yaw: b.yaw,
        velocity: Vector2::new(o.vx, o.vy),
        confidence: o.confidence,
        age: o.age,
        hits: o.hits,
    })
}

/// Points as packed little-endian f32 x, y, z triples.
pub fn pack_xyz(points: &[Point]) -> Vec<u8> {
    let mut out = Vec::with_capacity(points.len() * 12);
    for p in points {
        for v in [p.x, p.y, p.z] {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
    out
}

/// Packed little-endian f32 x, y, z triples as points (intensity 0).
pub fn unpack_xyz(bytes: &[u8]) -> Result<Vec<Point>, WireError> {
    if !bytes.len().is_multiple_of(12) {
        return Err(WireError::PackedLength {
            len: bytes.len(),
            stride: 12,
        });
    }
    let f = |c: &[u8]| f32::from_le_bytes([c[0], c[1], c[2], c[3]]);
    Ok(bytes
        .chunks_exact(12)
        .map(|c| Point::new(f(&c[0..4]), f(&c[4..8]), f(&c[8..12]), 0.0))
        .collect())
}

/// Points as packed little-endian f32 x, y, z, intensity quadruples (a `Scan`'s `points`).
pub fn pack_xyzi(points: &[Point]) -> Vec<u8> {
    bytemuck::cast_slice(points).to_vec()
}

/// A `Scan`'s packed x, y, z, intensity quadruples as points.
pub fn unpack_xyzi(bytes: &[u8]) -> Result<Vec<Point>, WireError> {
    if !bytes.len().is_multiple_of(16) {
        return Err(WireError::PackedLength {
            len: bytes.len(),
            stride: 16,
        });
    }
    // The buffer need not be aligned for f32: copy into an aligned vector.
    let mut points = vec![Point::default(); bytes.len() / 16];
    bytemuck::cast_slice_mut::<Point, u8>(&mut points).copy_from_slice(bytes);
    Ok(points)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pose_round_trips_and_rejects_non_rotations() {
        let pose = Isometry3::new(Vector3::new(1.0, -2.0, 0.5), Vector3::new(0.1, -0.2, 1.3));
        let back = pose_from_proto(&pose_to_proto(&pose)).unwrap();
        assert!((back.to_homogeneous() - pose.to_homogeneous()).norm() < 1e-12);
        let bad = proto::Pose {
            qw: 2.0,
            ..Default::default()
        };
        assert!(matches!(
            pose_from_proto(&bad),
            Err(WireError::NotARotation(_))
        ));
        let nan = proto::Pose {
            x: f64::NAN,
            qw: 1.0,
            ..Default::default()
        };
        assert_eq!(pose_from_proto(&nan), Err(WireError::NonFinite("pose")));
    }

    #[test]
    fn track_round_trips_and_rogue_objects_are_rejected() {
        let t = TrackState {
            id: 7,
            class: ObjectClass::Cyclist,
            center: Vector3::new(3.0, 4.0, 0.9),
            size: Vector3::new(1.8, 0.6, 1.7),
            yaw: 0.3,
            velocity: Vector2::new(4.0, 0.5),
            confidence: 0.8,
            age: 12,
            hits: 11,
        };
        let msg = track_to_proto(
            &t,
            &[0.0; 36],
            &[1.0; 308],
            pack_xyz(&[Point::new(1.0, 2.0, 3.0, 0.0)]),
        );
        assert_eq!(track_from_proto(&msg).unwrap(), t);
        assert_eq!(
            unpack_xyz(&msg.points).unwrap(),
            vec![Point::new(1.0, 2.0, 3.0, 0.0)]
        );

        let mut no_box = msg.clone();
        no_box.r#box = None;
        assert_eq!(track_from_proto(&no_box), Err(WireError::Missing("box")));
        let mut huge = msg.clone();
        huge.confidence = 3.0;
        assert!(matches!(
            track_from_proto(&huge),
            Err(WireError::OutOfRange { .. })
        ));
        let mut nan = msg;
        nan.vx = f64::NAN;
        assert_eq!(track_from_proto(&nan), Err(WireError::NonFinite("object")));
    }

    #[test]
    fn packed_points_check_their_length() {
        let pts = vec![
            Point::new(1.0, 2.0, 3.0, 0.5),
            Point::new(-1.0, 0.0, 9.0, 0.1),
        ];
        let bytes = pack_xyzi(&pts);
        assert_eq!(unpack_xyzi(&bytes).unwrap(), pts);
        assert_eq!(
            unpack_xyzi(&bytes[1..]),
            Err(WireError::PackedLength {
                len: 31,
                stride: 16
            })
        );
        assert_eq!(
            unpack_xyz(&[0; 13]),
            Err(WireError::PackedLength {
                len: 13,
                stride: 12
            })
        );
    }

    #[test]
    fn unknown_class_values_read_as_unknown() {
        assert_eq!(class_from_proto(99), ObjectClass::Unknown);
        assert_eq!(
            class_from_proto(class_to_proto(ObjectClass::Pedestrian).into()),
            ObjectClass::Pedestrian
        );
    }
}
