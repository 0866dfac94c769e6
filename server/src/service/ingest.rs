//! Reading an uploaded scan: a protobuf `Scan`, or a raw KITTI `.bin` / PCD file with its
//! timestamp and pose or OXTS packet given in the query or in headers.

use axum::http::{HeaderMap, StatusCode};
use prost::Message;
use trackd_client::api;
use trackd_perception::{Ego, Frame, Point, oxts::Oxts, wire};

/// Why an upload cannot be read: HTTP status, metrics reason and message.
#[derive(Debug)]
pub struct Refusal {
    /// 400 or 415.
    pub status: StatusCode,
    /// Metrics label.
    pub reason: &'static str,
    /// For the client.
    pub message: String,
}

impl Refusal {
    fn bad(message: impl Into<String>) -> Self {
        Self {
            status: StatusCode::BAD_REQUEST,
            reason: "bad_request",
            message: message.into(),
        }
    }
}

/// What the query of `POST /v1/scans` may carry.
#[derive(Debug, Default, serde::Deserialize, utoipa::IntoParams)]
#[into_params(parameter_in = Query)]
pub struct ScanQuery {
    /// Answer 202 as soon as the scan is queued.
    #[serde(rename = "async", default)]
    #[param(rename = "async")]
    pub queue_only: bool,
    /// Raw uploads: scan timestamp (seconds).
    pub timestamp: Option<f64>,
    /// Raw uploads: sensor pose `x,y,z,qw,qx,qy,qz` in the world frame.
    pub pose: Option<String>,
    /// Raw uploads: the OXTS packet, 30 comma-separated values.
    pub oxts: Option<String>,
}

/// The media type of a request, lower case, without parameters.
pub fn media_type(headers: &HeaderMap) -> Option<String> {
    let value = headers
        .get(axum::http::header::CONTENT_TYPE)?
        .to_str()
        .ok()?;
    Some(
        value
            .split(';')
            .next()
            .unwrap_or_default()
            .trim()
            .to_ascii_lowercase(),
    )
}

/// Reads an upload into a frame.
pub fn read_scan(
    content_type: Option<&str>,
    headers: &HeaderMap,
    query: &ScanQuery,
    body: &[u8],
) -> Result<Frame, Refusal> {
    match content_type {
        Some(api::PROTOBUF | "application/protobuf" | "application/vnd.google.protobuf") => {
            read_protobuf(body)
        }
        Some(api::KITTI_BIN | "application/octet-stream") => {
            let points = points_from_xyzi(body)?;
            raw_frame(points, headers, query)
        }
        Some(api::PCD | "text/x-pcd" | "application/vnd.pcd") => {
            let points = read_pcd(body)?;
            raw_frame(points, headers, query)
        }
        other => Err(Refusal {
            status: StatusCode::UNSUPPORTED_MEDIA_TYPE,
            reason: "unsupported_media_type",
            message: format!(
                "content type {:?} not accepted: use {}, {} or {}",
                other.unwrap_or("(none)"),
                api::PROTOBUF,
                api::KITTI_BIN,
                api::PCD
            ),
        }),
    }
}

fn read_protobuf(body: &[u8]) -> Result<Frame, Refusal> {
    let scan = trackd_proto::Scan::decode(body)
        .map_err(|e| Refusal::bad(format!("not a protobuf Scan: {e}")))?;
    if scan.version == 0 {
        return Err(Refusal::bad("not a trackd Scan: version field missing (0)"));
    }
    check_timestamp(scan.timestamp)?;
    let points = points_from_xyzi(&scan.points)?;
    let ego = match &scan.ego {
        None => Ego::None,
        Some(trackd_proto::scan::Ego::Oxts(o)) => Ego::Oxts(Oxts::from(o)),
        Some(trackd_proto::scan::Ego::Pose(p)) => {
            Ego::Pose(wire::pose_from_proto(p).map_err(|e| Refusal::bad(format!("pose: {e}")))?)
        }
    };
    Ok(Frame {
        timestamp: scan.timestamp,
        points,
        ego,
    })
}

fn check_timestamp(t: f64) -> Result<(), Refusal> {
    if t.is_finite() {
        Ok(())
    } else {
        Err(Refusal::bad(format!("timestamp {t} is not a number")))
    }
}

/// Packed little-endian f32 x, y, z, intensity quadruples.
fn points_from_xyzi(bytes: &[u8]) -> Result<Vec<Point>, Refusal> {
    wire::unpack_xyzi(bytes).map_err(|e| Refusal::bad(format!("points: {e} (truncated scan?)")))
}

fn read_pcd(body: &[u8]) -> Result<Vec<Point>, Refusal> {
    // The PCD reader reads files; a temporary file keeps one parser for files and uploads.
    let mut file = tempfile::NamedTempFile::new()
        .map_err(|e| Refusal::bad(format!("PCD: no temporary file: {e}")))?;
    std::io::Write::write_all(&mut file, body)
        .map_err(|e| Refusal::bad(format!("PCD: writing temporary file: {e}")))?;
    trackd_dataset::pcd::read_pcd(file.path()).map_err(|e| Refusal::bad(format!("PCD: {e}")))
}

fn header_text<'a>(headers: &'a HeaderMap, name: &str) -> Option<&'a str> {
    headers.get(name).and_then(|v| v.to_str().ok())
}

fn numbers(what: &str, text: &str, expected: usize) -> Result<Vec<f64>, Refusal> {
    let values: Vec<f64> = text
        .split(',')
        .map(|v| v.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| Refusal::bad(format!("{what}: {e}")))?;
    if values.len() != expected || values.iter().any(|v| !v.is_finite()) {
        return Err(Refusal::bad(format!(
            "{what}: expected {expected} finite comma-separated numbers, got {:?}",
            text
        )));
    }
    Ok(values)
}

fn raw_frame(points: Vec<Point>, headers: &HeaderMap, query: &ScanQuery) -> Result<Frame, Refusal> {
    let timestamp = match query.timestamp {
        Some(t) => t,
        None => header_text(headers, api::HEADER_TIMESTAMP)
            .ok_or_else(|| {
                Refusal::bad(format!(
                    "raw scans need a timestamp: ?timestamp=SECONDS or header {}",
                    api::HEADER_TIMESTAMP
                ))
            })?
            .trim()
            .parse()
            .map_err(|e| Refusal::bad(format!("timestamp: {e}")))?,
    };
    check_timestamp(timestamp)?;
    let pose = query
        .pose
        .as_deref()
        .or_else(|| header_text(headers, api::HEADER_POSE));
    let oxts = query
        .oxts
        .as_deref()
        .or_else(|| header_text(headers, api::HEADER_OXTS));
    let ego = match (pose, oxts) {
        (Some(_), Some(_)) => return Err(Refusal::bad("give a pose or an OXTS packet, not both")),
        (Some(text), None) => {
            let v = numbers("pose", text, 7)?;
            let p = trackd_proto::Pose {
                x: v[0],
                y: v[1],
                z: v[2],
                qw: v[3],
                qx: v[4],
                qy: v[5],
                qz: v[6],
            };
            Ego::Pose(wire::pose_from_proto(&p).map_err(|e| Refusal::bad(format!("pose: {e}")))?)
        }
        (None, Some(text)) => {
            let v = numbers("oxts", text, Oxts::FIELDS)?;
            let mut values = [0.0; Oxts::FIELDS];
            values.copy_from_slice(&v);
            Ego::Oxts(Oxts::from_values(&values))
        }
        (None, None) => Ego::None,
    };
    Ok(Frame {
        timestamp,
        points,
        ego,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bin(points: &[[f32; 4]]) -> Vec<u8> {
        points
            .iter()
            .flatten()
            .flat_map(|v| v.to_le_bytes())
            .collect()
    }

    #[test]
    fn a_kitti_bin_with_pose_header_reads() {
        let mut headers = HeaderMap::new();
        headers.insert(api::HEADER_TIMESTAMP, "12.5".parse().expect("header"));
        headers.insert(api::HEADER_POSE, "1,2,3,1,0,0,0".parse().expect("header"));
        let body = bin(&[[1.0, 2.0, 3.0, 0.5], [4.0, 5.0, 6.0, 0.0]]);
        let frame =
            read_scan(Some(api::KITTI_BIN), &headers, &ScanQuery::default(), &body).expect("reads");
        assert_eq!(frame.points.len(), 2);
        assert_eq!(frame.points[1].y, 5.0);
        assert_eq!(frame.timestamp, 12.5);
        let Ego::Pose(p) = frame.ego else {
            panic!("pose expected")
        };
        assert_eq!(p.translation.vector.z, 3.0);
    }

    #[test]
    fn bad_uploads_are_refused_with_reasons() {
        let h = HeaderMap::new();
        let q = ScanQuery {
            timestamp: Some(1.0),
            ..Default::default()
        };
        let truncated = read_scan(Some(api::KITTI_BIN), &h, &q, &[0u8; 18]).expect_err("truncated");
        assert_eq!(truncated.status, StatusCode::BAD_REQUEST);
        assert!(
            truncated.message.contains("multiple of 16"),
            "{}",
            truncated.message
        );
        let garbage =
            read_scan(Some(api::PROTOBUF), &h, &q, b"\xff\xff\xff garbage").expect_err("garbage");
        assert_eq!(garbage.status, StatusCode::BAD_REQUEST);
        let media = read_scan(Some("text/plain"), &h, &q, b"").expect_err("media");
        assert_eq!(media.status, StatusCode::UNSUPPORTED_MEDIA_TYPE);
        let no_time =
            read_scan(Some(api::KITTI_BIN), &h, &ScanQuery::default(), &[]).expect_err("time");
        assert!(no_time.message.contains("timestamp"));
        let q_bad_pose = ScanQuery {
            timestamp: Some(1.0),
            pose: Some("1,2,3".into()),
            ..Default::default()
        };
        assert!(read_scan(Some(api::KITTI_BIN), &h, &q_bad_pose, &[]).is_err());
    }

    #[test]
    fn a_protobuf_scan_reads_with_its_oxts() {
        let scan = trackd_proto::Scan {
            version: trackd_proto::SCHEMA_VERSION,
            timestamp: 3.0,
            points: bin(&[[1.0, 0.0, 0.0, 0.0]]),
            ego: Some(trackd_proto::scan::Ego::Oxts(trackd_proto::Oxts {
                lat: 49.0,
                ..Default::default()
            })),
        };
        let frame = read_scan(
            Some(api::PROTOBUF),
            &HeaderMap::new(),
            &ScanQuery::default(),
            &scan.encode_to_vec(),
        )
        .expect("reads");
        assert!(matches!(frame.ego, Ego::Oxts(o) if o.lat == 49.0));
    }
}
